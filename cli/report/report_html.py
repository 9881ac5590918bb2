"""The page of a diagnosis report: DIR/index.html, self-contained (inline style, figures by
relative path, no script, nothing fetched from the network).

In this order: the headline (what the model search kept, the held-out MAE factor of d̂, MAE over
the Cramér–Rao bound before and after: report_html_search), the search's steps and the figure of
each term as it was fitted, the paper's figures on the data, the residual tests as evidence
(report_html_findings), the error of the paper's model before and after its compensation, and
what was run. Every key of the diagnosis JSON is optional: what is absent is said, not guessed.
"""

import os

from report_html_cells import escape as _e
from report_html_cells import mm, mm2, number as _number, row as _row, td as _td
from report_html_findings import evidence_section
from report_html_search import headline_section, search_section, terms_section

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
    "bias_corrected_mean": "mean of y − Hθ̂ − Σπ̂ᵢμ̂ᵢ",
    "em_distance": "d̂ (EM testing)",
}


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


def _moments_cells(m):
    m = m or {}
    return [_td(mm(m.get("mean_error_mm"))), _td(mm(m.get("mean_absolute_error_mm"))),
            _td(mm(m.get("rmse_mm"))), _td(mm2(m.get("absolute_error_variance_mm2")))]


MOMENT_HEADS = "<th>ME mm</th><th>MAE mm</th><th>RMSE mm</th><th>var |e| mm²</th>"


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
                 "temperature bias and centred (less the modes' common offset Σπ̂ᵢμ̂ᵢ, which the "
                 "paper's mean of y − Hθ̂ carries), and d̂ (after). The MAE factor is "
                 "MAE(ȳ) / MAE(d̂).</p>")
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


def write_page(path, data, figures, skipped, finding_figures=None, term_figures=None):
    c = data.context
    title = f"tofcomp diagnose: {c.get('source', 'report')}"
    body = [
        f"<h1>{_e(title)}</h1>",
        headline_section(data.diagnosis),
        f"<p>{_e(c.get('software_version', 'tofcomp'))}; after Alhashimi, Varagnolo and "
        f"Gustafsson, <i>Joint Temperature-Lasing Mode Compensation for Time-of-Flight LiDAR "
        f"Sensors</i>, Sensors 2015. Sections: <a href=\"#search\">the search</a>, "
        f"<a href=\"#terms\">its terms</a>, <a href=\"#figures\">the paper's figures</a>, "
        f"<a href=\"#evidence\">evidence</a>, <a href=\"#errors\">errors</a>, "
        f"<a href=\"#run\">what was run</a>.</p>",
        search_section(data.diagnosis),
        terms_section(data.diagnosis, term_figures or []),
        figures_section(figures, skipped),
        evidence_section(data.diagnosis, finding_figures or {}),
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
