"""The page of a diagnosis report: DIR/index.html, self-contained (inline style, figures by
relative path, no script, nothing fetched from the network).

It shows the paper's figures on the data, then the findings of the diagnosis (the JSON of
`tofcomp diagnose --json`), each with the figure of what its test measures
(report_figures_findings), the extension kept, and the error of d̂ before and after, per window
length. Every key of the diagnosis JSON is optional: what is absent is said, not guessed.
"""

import html
import math
import os
import re

STYLE = """
body { font-family: sans-serif; max-width: 60em; margin: 2em auto; padding: 0 1em; color: #222;
       line-height: 1.45; }
h1 { font-size: 1.5em; } h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ccc; }
h3 { font-size: 1.1em; margin-top: 1.5em; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f1f1f1; } td.text, th.text { text-align: left; }
tr.significant td { background: #fff3d6; }
figure { margin: 2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.92em; color: #333; margin-top: 0.4em; }
.summary { background: #f4f7fb; border-left: 4px solid #1f4e9c; padding: 0.6em 1em; }
code { background: #f1f1f1; padding: 0 0.2em; }
"""

ESTIMATOR_NAMES = {
    "raw_mean": "ȳ (raw window mean)",
    "bias_corrected_mean": "mean of y − Hθ̂",
    "em_distance": "d̂ (EM testing)",
}


def _e(text):
    return html.escape(str(text))


def _number(value, spec):
    if value is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return "–"
    if isinstance(value, float) and not math.isfinite(value):
        return "–"
    return format(value, spec)


def mm(value):
    return _number(value, ".3f")


def mm2(value):
    return _number(value, ".4f")


def statistic(value):
    return _number(value, ".4g")


def p_value(value):
    return _number(value, ".3g")


def _row(cells, cls=None):
    attribute = f' class="{cls}"' if cls else ""
    return f"<tr{attribute}>" + "".join(cells) + "</tr>"


def _td(text, cls=None):
    return f'<td class="{cls}">{_e(text)}</td>' if cls else f"<td>{_e(text)}</td>"


def summary_section(diagnosis):
    named = diagnosis.get("named")
    if named is None:
        lacks = "The diagnosis names no effect (no <code>named</code> in its JSON)."
    elif named == "none":
        lacks = ("No finding is significant at 5 % family-wise: the paper's model (Eq. 8) "
                 "explains these data.")
    else:
        lacks = f"The paper's model lacks: <b>{_e(named)}</b>."
    extension = diagnosis.get("extension")
    if extension is None:
        kept = "No extension was fitted, so none is kept."
    elif extension.get("kept"):
        kept = f"Extension kept: {_e(extension.get('model', extension.get('effect', '')))}."
    else:
        kept = ("The extension fitted was not kept: it did not both raise the held-out "
                "likelihood and cut the held-out MAE of d̂ by at least 1 %.")
    return f'<p class="summary">{lacks} {kept}</p>'


def figures_section(figures, skipped):
    parts = ["<h2 id=\"figures\">The paper's figures on these data</h2>"]
    if skipped:
        parts.append("<p>Left out, as the data do not allow them: "
                     + ", ".join(f"Fig. {_e(n)}" for n in skipped) + ".</p>")
    for f in figures:
        parts.append(
            f'<figure id="fig{_e(f.number)}"><img src="{_e(f.file)}" alt="Fig. {_e(f.number)}: '
            f'{_e(f.paper)}"><figcaption><b>Fig. {_e(f.number)}</b> (the paper: {_e(f.paper)}). '
            f"{_e(f.caption)}</figcaption></figure>")
    return "\n".join(parts)


def findings_section(diagnosis, finding_figures=None):
    parts = ['<h2 id="findings">Findings</h2>']
    findings = diagnosis.get("findings")
    if not findings:
        parts.append("<p>The diagnosis reported no findings.</p>")
        return "\n".join(parts)
    parts.append("<p>Each candidate effect the paper's model lacks, tested on the "
                 "mode-compensated residuals; significant at 5 % family-wise (Bonferroni), "
                 "most significant first. Below the table, each finding again with the figure "
                 "of what its test measures.</p>")
    head = "".join(f'<th class="text">{h}</th>' for h in ("effect", "test", "against")) + "".join(
        f"<th>{h}</th>" for h in ("statistic", "p-value", "z", "significant"))
    rows = [f"<table><tr>{head}</tr>"]
    for f in findings:
        significant = f.get("significant")
        rows.append(_row([
            _td(f.get("effect", "–"), "text"), _td(f.get("test", "–"), "text"),
            _td(f.get("covariate", "–"), "text"), _td(statistic(f.get("statistic"))),
            _td(p_value(f.get("p_value"))), _td(_number(f.get("z"), ".2f")),
            _td("yes" if significant else ("no" if significant is not None else "–")),
        ], "significant" if significant else None))
    rows.append("</table>")
    parts.append("\n".join(rows))
    parts.append(finding_figures_section(findings, finding_figures or {}))
    return "\n".join(parts)


def _slug(effect):
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
            f"{statistic(f.get('statistic'))}, p-value {p_value(f.get('p_value'))}, {verdict}.")


def finding_figures_section(findings, finding_figures):
    """Each finding with the figure of what its test measures, in the table's order."""
    parts = ['<h3 id="finding-figures">What each test measures, on these data</h3>']
    for f in findings:
        effect = f.get("effect", "–")
        figure = finding_figures.get(effect)
        head = f"<b>Finding: {_e(effect)}</b>. {_e(_finding_numbers(f))}"
        if figure is None:
            parts.append(f'<p id="finding-{_e(_slug(effect))}">{head} No figure: the data do '
                         f"not allow one.</p>")
            continue
        parts.append(
            f'<figure id="finding-{_e(_slug(effect))}" class="finding"><img src="{_e(figure.file)}"'
            f' alt="Finding {_e(effect)}: {_e(figure.paper)}"><figcaption>{head} '
            f"{_e(figure.caption)}</figcaption></figure>")
    return "\n".join(parts)


def _moments_cells(m):
    m = m or {}
    return [_td(mm(m.get("mean_error_mm"))), _td(mm(m.get("mean_absolute_error_mm"))),
            _td(mm(m.get("rmse_mm"))), _td(mm2(m.get("absolute_error_variance_mm2")))]


MOMENT_HEADS = "<th>ME mm</th><th>MAE mm</th><th>RMSE mm</th><th>var |e| mm²</th>"


def extension_section(diagnosis):
    parts = ['<h2 id="extension">The extension</h2>']
    extension = diagnosis.get("extension")
    named = diagnosis.get("named")
    if extension is None:
        why = ("nothing is significant, so the paper's model stands" if named == "none"
               else f"no extension is fitted for {_e(named)} yet" if named
               else "the diagnosis names no effect")
        parts.append(f"<p>None kept: {why}.</p>")
        return "\n".join(parts)
    verdict = ("kept" if extension.get("kept") else
               "not kept: it did not both raise the held-out likelihood and cut the held-out "
               "MAE of d̂ by at least 1 %")
    parts.append(f"<p>For <b>{_e(extension.get('effect', '–'))}</b>: "
                 f"{_e(extension.get('model', '–'))}; {verdict}.</p>")
    parameters = extension.get("parameters") or {}
    if parameters:
        parts.append("<table><tr><th class=\"text\">parameter</th><th>value</th></tr>" + "".join(
            _row([_td(name, "text"), _td(statistic(value))]) for name, value in parameters.items())
            + "</table>")
    gain = extension.get("held_out_log_likelihood_gain")
    if gain is not None:
        parts.append(f"<p>Held-out log-likelihood gain: {_e(_number(gain, '.1f'))}.</p>")
    errors = extension.get("errors") or []
    if errors:
        parts.append("<p>The error of d̂ on the held-out half, the paper's model (before) "
                     "against the extended one (after), per window length:</p>")
        rows = ["<table><tr><th rowspan=\"2\">window</th><th rowspan=\"2\">windows</th>"
                "<th colspan=\"4\">before (Eq. 8)</th><th colspan=\"4\">after (extended)</th>"
                "<th rowspan=\"2\">MAE factor</th></tr>",
                f"<tr>{MOMENT_HEADS}{MOMENT_HEADS}</tr>"]
        for e in errors:
            before = e.get("before") or {}
            rows.append(_row([_td(_number(e.get("window"), "d")),
                              _td(_number(before.get("count"), "d"))]
                             + _moments_cells(before) + _moments_cells(e.get("after"))
                             + [_td(_number(e.get("mae_factor"), ".2f"))]))
        rows.append("</table>")
        parts.append("\n".join(rows))
    return "\n".join(parts)


def compensation_section(data):
    """The error before and after the paper's compensation, from moments.csv."""
    parts = ['<h2 id="errors">The error before and after the compensation</h2>']
    m = data.moments
    windows = data.context.get("windows", [])
    if m is None or not windows:
        parts.append("<p>No window of the held-out part could be evaluated.</p>")
        return "\n".join(parts)
    parts.append("<p>The paper's model trained on the first half, on every window of the held-out "
                 "half (§8.4): the raw window mean ȳ (before), the mean corrected by the "
                 "temperature bias, and d̂ (after). The MAE factor is MAE(ȳ) / MAE(d̂).</p>")
    rows = [f"<table><tr><th>window</th><th class=\"text\">estimator</th><th>windows</th>"
            f"{MOMENT_HEADS}<th>MAE factor</th></tr>"]
    for w in windows:
        chosen = {e: i for i, e in enumerate(m["estimator"]) if m["window"][i] == w}
        if "raw_mean" not in chosen or "em_distance" not in chosen:
            continue
        factor = m["mean_absolute_error_mm"][chosen["raw_mean"]] / m["mean_absolute_error_mm"][
            chosen["em_distance"]]
        for estimator, name in ESTIMATOR_NAMES.items():
            i = chosen[estimator]
            moments = {column: float(m[column][i]) for column in
                       ("mean_error_mm", "mean_absolute_error_mm", "rmse_mm",
                        "absolute_error_variance_mm2")}
            rows.append(_row([_td(int(w)), _td(name, "text"), _td(int(m["count"][i]))]
                             + _moments_cells(moments)
                             + [_td(_number(float(factor), ".2f") if estimator == "em_distance"
                                    else "")]))
    rows.append("</table>")
    parts.append("\n".join(rows))
    return "\n".join(parts)


def run_section(data):
    c = data.context
    glr = c.get("glr", {})
    cost = c.get("em_test_cost", {})
    calibration = c.get("calibration", {})
    items = [
        f"Data: <code>{_e(c.get('source', '–'))}</code>, beam {_e(c.get('beam', '–'))}; "
        f"split at t = {_e(_number(c.get('split_time_s'), '.0f'))} s (the power-on nearest the "
        f"middle): {_e(c.get('training_samples', '–'))} ranges to train on, "
        f"{_e(c.get('test_samples', '–'))} held out.",
        f"Model: basis {_e(calibration.get('basis', '–'))}, "
        f"{len(calibration.get('modes', []))} lasing modes, EM training "
        f"{_e(c.get('em_training_iterations', '–'))} iterations.",
        f"Windows: {_e(', '.join(str(w) for w in c.get('windows', [])))} (Fig. 16-17 and the "
        f"tables), {_e(', '.join(str(w) for w in c.get('moment_windows', [])))} (Fig. 18-19); "
        f"window starts {_e(c.get('stride', '–'))} range(s) apart.",
        f"Algorithm 2 (Fig. 9-10): polynomial orders "
        f"1..{_e(glr.get('max_polynomial_order', '–'))} (Legendre form) and Fourier orders "
        f"1..{_e(glr.get('max_fourier_order', '–'))} with "
        f"f0 = {_e(_number(glr.get('fourier_f0_per_c'), '.4g'))} /°C (half a period over the "
        f"training temperatures), each trained on {_e(glr.get('training_samples', '–'))} ranges; "
        f"{_e(_number(glr.get('seconds'), '.1f'))} s in all.",
        f"Cost (Fig. 15): {_e(', '.join(cost.get('bases', [])))}; {_e(cost.get('steps', '–'))} "
        f"EM test steps, best of {_e(cost.get('repetitions', '–'))} runs.",
        "The data behind every figure are the CSV files in <code>data/</code>; the diagnosis "
        "is <code>data/diagnosis.json</code>.",
    ]
    return ('<h2 id="run">What was run</h2><ul>'
            + "".join(f"<li>{item}</li>" for item in items) + "</ul>")


def write_page(path, data, figures, skipped, finding_figures=None):
    c = data.context
    title = f"tofcomp diagnose: {c.get('source', 'report')}"
    body = [
        f"<h1>{_e(title)}</h1>",
        f"<p>{_e(c.get('software_version', 'tofcomp'))}; after Alhashimi, Varagnolo and "
        f"Gustafsson, <i>Joint Temperature-Lasing Mode Compensation for Time-of-Flight LiDAR "
        f"Sensors</i>, Sensors 2015. Sections: <a href=\"#figures\">figures</a>, "
        f"<a href=\"#findings\">findings</a>, <a href=\"#extension\">extension</a>, "
        f"<a href=\"#errors\">errors</a>, <a href=\"#run\">what was run</a>.</p>",
        summary_section(data.diagnosis),
        figures_section(figures, skipped),
        findings_section(data.diagnosis, finding_figures),
        extension_section(data.diagnosis),
        compensation_section(data),
        run_section(data),
    ]
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{_e(title)}</title><style>{STYLE}</style></head><body>\n"
            + "\n".join(body) + "\n</body></html>\n")
    temporary = path + ".tmp"
    with open(temporary, "w", encoding="utf-8") as f:
        f.write(page)
    os.replace(temporary, path)  # a reader never sees half a page
