"""The parts of the report's page that show the model search (the "search" object of
`tofcomp diagnose --json`, cli/search_format.hpp): the headline, first on the page (what was
named and kept, the held-out MAE factor of d̂, MAE over the Cramér–Rao bound before and after,
each number as the JSON has it), the steps of the forward selection, and the figure of each term
(report_figures_terms). Every key is optional: what is absent shows as "–".
"""

from report_figures_terms import fitted_text, verdict_text
from report_html_cells import (escape, figure_html, mm, number, p_value, ratio, row, statistic,
                               td)

CANDIDATES_SHOWN = 5  # per step, in the table of candidates


def _alpha_text(search):
    return f"α = {number(search.get('alpha'), 'g')} family-wise, max-T over the step's candidates (sign flips of the runs)"


def _windows(search):
    return sorted((search.get("mae_mm") or {}).get("base", {}), key=int)


def _step_of(search, effect):
    for i, step in enumerate(search.get("steps") or []):
        named = (step.get("candidates") or [{}])[0]
        if named.get("effect") == effect:
            return i + 1, step
    return None, None


def search_verdict(search, effect):
    """What the search made of an effect, in words: kept, named but not kept, or not named."""
    if any(k.get("effect") == effect for k in search.get("kept") or []):
        return "kept"
    step, _ = _step_of(search, effect)
    return f"named at step {step}, not kept" if step else "not named"


def headline_section(diagnosis):
    search = diagnosis.get("search") or {}
    kept = search.get("kept") or []
    best = search.get("best")
    if kept:
        verdict = ("The model search kept <b>" + escape(", ".join(k["effect"] for k in kept))
                   + "</b> (" + escape("; ".join(k["term"] for k in kept)) + ").")
    else:
        verdict = ("The model search kept <b>nothing</b>: the paper's model (Eq. 8) explains "
                   "these data (" + escape(_alpha_text(search)) + ").")
    if best is None:
        named = "No candidate could be fitted."
    elif kept and best.get("effect") == kept[0].get("effect"):
        named = f"Named first: {escape(best['effect'])}, kept."
    else:
        step = (search.get("steps") or [{}])[0]
        first = (step.get("candidates") or [{}])[0]
        named = (f"Named first: {escape(best['effect'])} ({escape(best['term'])}), not kept: "
                 f"held-out p-value {p_value(first.get('p_value'))} &gt; "
                 f"{p_value(step.get('critical_p'))}.")
    mae = search.get("mae_mm") or {}
    factor = search.get("mae_factor") or {}
    bound = search.get("cramer_rao_mae_mm") or {}
    over = search.get("mae_over_cramer_rao") or {}
    rows = ['<table id="headline-errors"><tr><th>window</th><th>MAE of d̂, trained (mm)</th>'
            "<th>MAE of d̂, with the kept terms (mm)</th><th>MAE factor</th>"
            "<th>Cramér–Rao bound (mm)</th><th>MAE / bound, trained</th>"
            "<th>MAE / bound, with the kept terms</th></tr>"]
    for w in _windows(search):
        rows.append(row([td(w), td(mm(mae.get("base", {}).get(w))),
                         td(mm(mae.get("final", {}).get(w))), td(ratio(factor.get(w))),
                         td(mm(bound.get(w))), td(ratio(over.get("base", {}).get(w))),
                         td(ratio(over.get("final", {}).get(w)))]))
    rows.append("</table>")
    not_compared = search.get("windows_not_compared") or []
    if not_compared:
        rows.append(f'<p id="windows-not-compared">Not compared: window '
                    f"{escape(', '.join(str(w) for w in not_compared))}, longer than this "
                    f"record's held-out blocks ({escape(search.get('block', '–'))} ranges).</p>")
    return (f'<div class="summary" id="headline"><p>{verdict} {named}</p>'
            f"<p>The error of d̂ on held-out windows (each window scored by the fold that did not "
            f"see it), the trained model against the model with the kept terms; the MAE factor "
            f"is the first over the second:</p>" + "\n".join(rows) + "</div>")


def _step_errors(step):
    return ", ".join(f"{e.get('window')}: {ratio(e.get('mae_factor'))}"
                     for e in step.get("errors") or [])


def search_section(diagnosis):
    search = diagnosis.get("search") or {}
    parts = ['<h2 id="search">The model search</h2>',
             f"<p>{escape(search.get('candidates_per_step', '–'))} candidates of the grammar "
             f"(parameter × covariate × form, and structure) per step, each fitted by EM on one "
             f"of two folds of {escape(search.get('blocks', '–'))} blocks of "
             f"{escape(search.get('block', '–'))} ranges and scored on the other; the candidate "
             f"with the largest held-out gain is named, and kept when its p-value is at most "
             f"the step's level ({escape(_alpha_text(search))}). Forward selection: each kept "
             f"term is held while the next step searches.</p>"]
    head = ("<tr><th>step</th><th class=\"text\">named</th><th class=\"text\">term</th>"
            "<th>gain per range</th><th>t</th><th>p-value</th><th>level (max-T)</th>"
            "<th class=\"text\">verdict</th><th class=\"text\">MAE factor by window</th></tr>")
    rows = [f'<table id="search-steps">{head}']
    for i, step in enumerate(search.get("steps") or []):
        named = (step.get("candidates") or [{}])[0]
        rows.append(row([td(i + 1), td(named.get("effect", "–"), "text"),
                         td(named.get("term", "–"), "text"),
                         td(number(named.get("gain_per_range"), ".2e")),
                         td(ratio(named.get("t"))), td(p_value(named.get("p_value"))),
                         td(p_value(step.get("critical_p"))),
                         td("kept" if step.get("kept") else "not kept", "text"),
                         td(_step_errors(step), "text")],
                        "significant" if step.get("kept") else None))
    rows.append("</table>")
    parts.append("\n".join(rows))
    for i, step in enumerate(search.get("steps") or []):
        candidates = step.get("candidates") or []
        parts.append(f"<p>Step {i + 1}: the first {min(CANDIDATES_SHOWN, len(candidates))} of "
                     f"{len(candidates)} candidates, the named one first, then by held-out gain "
                     f"(all are in <code>data/diagnosis.json</code>)"
                     f"</p>")
        table = ["<table><tr><th class=\"text\">effect</th><th class=\"text\">term</th>"
                 "<th>gain per range</th><th>t</th><th>p-value</th><th class=\"text\">fit</th>"
                 "</tr>"]
        for c in candidates[:CANDIDATES_SHOWN]:
            fit = "screen" if c.get("screened_only") else "converged"
            table.append(row([td(c.get("effect", "–"), "text"), td(c.get("term", "–"), "text"),
                              td(number(c.get("gain_per_range"), ".2e")), td(ratio(c.get("t"))),
                              td(p_value(c.get("p_value")) if "error" not in c
                                 else "not fitted: " + str(c["error"])),
                              td(fit if "error" not in c else "–", "text")]))
        table.append("</table>")
        parts.append("\n".join(table))
    return "\n".join(parts)


def terms_section(diagnosis, term_figures):
    """Each term the search kept, and the candidate it named last and did not keep, with its
    figure."""
    search = diagnosis.get("search") or {}
    parts = ['<h2 id="terms">The terms, as the search fitted them</h2>']
    if not term_figures:
        parts.append("<p>No term: the search named no candidate it could fit.</p>")
        return "\n".join(parts)
    parts.append("<p>Each kept term drawn with the values the search fitted on the whole record, "
                 "the values the calibration with the kept terms holds "
                 "(<code>--calibration-output</code>), over the residuals of the whole record "
                 "under that calibration; a candidate named but not kept is drawn without a "
                 "fitted effect.</p>")
    alpha = _alpha_text(search)
    for entry, figure in term_figures:
        kept = bool(entry.get("kept"))
        head = (f"<b>{'Term' if kept else 'Candidate'} {escape(entry['index'])}: "
                f"{escape(entry['effect'])}</b> ({escape(entry['term'])}). "
                f"{escape(verdict_text(entry, alpha))} {escape(fitted_text(entry))} "
                f"Held-out gain {escape(statistic(entry.get('held_out_gain')))} nats.")
        parts.append(figure_html(f"term-{entry['index']}",
                                 "term kept" if kept else "term not-kept", figure, head))
    return "\n".join(parts)
