"""The evidence part of the report's page: the residual tests of the trained model (the
"findings" of `tofcomp diagnose --json`, core/residual_diagnosis.hpp), each with its figure
(report_figures_findings) and, beside the test's own verdict, the search's verdict on the same
effect: the tests are evidence, the search names and keeps.
"""

import re

from report_html_cells import escape, figure_html, number, p_value, row, statistic, td
from report_html_search import search_verdict


def slug(effect):
    return re.sub(r"[^a-z0-9]+", "-", str(effect).lower()).strip("-")


def _finding_numbers(f):
    """The finding's statistic and p-value as the table shows them; for one more mode, the
    statistic is the log of the split likelihood ratio, a held-out log-likelihood gain."""
    name = ("log-likelihood gain log T" if f.get("test") == "split likelihood ratio"
            else "statistic")
    significant = f.get("significant")
    verdict = ("significant at 5 % family-wise" if significant else "not significant"
               if significant is not None else "significance not given")
    return (f"{f.get('test', '–')} ({f.get('covariate', '–')}): {name} "
            f"{statistic(f.get('statistic'))} ({_under_the_model(f)} under the trained model), "
            f"p-value {p_value(f.get('p_value'))} against {f.get('reference', '–')} (its "
            f"textbook law: {p_value(f.get('textbook_p_value'))}), {verdict}.")


def _under_the_model(f):
    """The statistic's mean ± deviation over the trained model's draws, an expected count, or
    '–' (the finding's null_mean and null_std)."""
    mean, std = f.get("null_mean"), f.get("null_std")
    if mean is None:
        return "–"
    return f"{statistic(mean)} ± {statistic(std)}" if std is not None else statistic(mean)


def _search_words(search, f):
    effect = f.get("search_effect")
    if effect is None:
        return ("The search has no term for it: a symptom that any effect in time shows.")
    verdict = search_verdict(search, effect)
    if verdict == "kept":
        return (f"The search kept {effect}: its term, as fitted, is drawn in the section of the "
                f"terms above.")
    return f"The search's verdict on {effect}: {verdict}."


def evidence_section(diagnosis, finding_figures):
    parts = ['<h2 id="evidence">Evidence: the residual tests of the trained model</h2>']
    findings = diagnosis.get("findings")
    if not findings:
        parts.append("<p>The diagnosis reported no residual tests.</p>")
        return "\n".join(parts)
    parts.append("<p>Each test looks in the residuals of the trained model (Eq. 8 without any "
                 "of the search's terms) for one effect, significant at 5 % family-wise "
                 "(Bonferroni over the tests), most significant first. Each statistic is judged "
                 "against draws of the trained model itself, the ranges rounded as the device "
                 "rounds them (the column 'under the model' gives the draws' mean and "
                 "deviation): the rounding alone moves these statistics far from their textbook "
                 "laws on data that hold the model. They are evidence, not the verdict: on data "
                 "with an effect, several tests fire, and the smallest p-value is not the best "
                 "explanation; the search above decides. Each figure draws the data and the "
                 "trained model, never a fitted effect.</p>")
    head = "".join(f'<th class="text">{h}</th>' for h in ("effect", "test", "against")) + "".join(
        f"<th>{h}</th>" for h in ("statistic", "under the model", "p-value", "z",
                                  "significant")) + '<th class="text">the search</th>'

    search = diagnosis.get("search") or {}
    rows = [f'<table id="findings"><tr>{head}</tr>']
    for f in findings:
        significant = f.get("significant")
        effect = f.get("search_effect")
        rows.append(row([
            td(f.get("effect", "–"), "text"), td(f.get("test", "–"), "text"),
            td(f.get("covariate", "–"), "text"), td(statistic(f.get("statistic"))),
            td(_under_the_model(f)), td(p_value(f.get("p_value"))),
            td(number(f.get("z"), ".2f")),
            td("yes" if significant else ("no" if significant is not None else "–")),
            td(search_verdict(search, effect) if effect else "–", "text"),
        ], "significant" if significant else None))
    rows.append("</table>")
    parts.append("\n".join(rows))
    parts.append('<h3 id="finding-figures">What each test measures, on these data</h3>')
    for f in findings:
        effect = f.get("effect", "–")
        figure = finding_figures.get(effect)
        head = (f"<b>Evidence: {escape(effect)}</b>. {escape(_finding_numbers(f))} "
                f"{escape(_search_words(search, f))}")
        if figure is None:
            parts.append(f'<p id="finding-{escape(slug(effect))}">{head} No figure: the data do '
                         f"not allow one.</p>")
            continue
        parts.append(figure_html(f"finding-{slug(effect)}", "finding", figure, head))
    return "\n".join(parts)
