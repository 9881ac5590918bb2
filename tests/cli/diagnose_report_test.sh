#!/usr/bin/env bash
# End to end through the real binary: `tofcomp diagnose --report DIR --json --calibration-output`
# on a short time-drift scenario, then checks on the report: the headline comes first and carries
# the numbers of the JSON's search (what was kept, the held-out MAE of d̂ before and after, the
# factor, MAE over the Cramér–Rao bound before and after); each kept term has its figure, drawn
# from data that hold the values the calibration file holds (its coefficients, and a curve that
# is the term those coefficients give), and the candidate named but not kept has a figure that
# says so and draws no fitted effect; every paper figure is there (Fig. 4 among them);
# index.html names only PNGs that exist, are PNG and are not trivial, and no PNG goes unnamed;
# the residual tests are evidence, each with its figure captioned as such with its numbers and
# the search's verdict; the centred mean of y − Hθ̂; nothing is fetched from the network. Then
# the renderer alone on a search that kept nothing; then the errors a user meets, before any long
# work: a DIR that cannot be made, a Python without matplotlib.
set -euo pipefail
tofcomp=$1
root=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
datasheet="$root/config/lms200-datasheet.yaml"
renderer="$(dirname "$tofcomp")/../share/tofcomp/report/diagnosis_report.py"
test -f "$renderer" || { echo "the renderer is not beside the binary: $renderer"; exit 1; }

# A Python with matplotlib and numpy, as the binary looks for one (cli/report_renderer.hpp).
python=""
for candidate in ${TOFCOMP_PYTHON:-} python3 /usr/bin/python3; do
  if "$candidate" "$renderer" --check > /dev/null 2>&1; then python=$candidate; break; fi
done
test -n "$python" \
  || { echo "no Python with matplotlib and numpy (apt-get install python3-matplotlib)"; exit 1; }

"$tofcomp" -q simulate "$root/tests/cli/report-time-drift.yaml" -o "$work/drift.csv"
"$tofcomp" -q diagnose "$work/drift.csv" --datasheet "$datasheet" --report "$work/report" --json \
  --calibration-output "$work/calibration.yaml" > "$work/diagnosis.json"

# The checks of one rendered report; argv: report dir, diagnosis JSON, expected figures, and the
# calibration file with the kept terms (or "-" when the search kept nothing).
cat > "$work/check_report.py" <<'PY'
import csv, html, json, math, os, re, sys

directory, diagnosis_path, calibration_path = sys.argv[1], sys.argv[2], sys.argv[4]
figures_expected = sys.argv[3].split(",")
page = open(os.path.join(directory, "index.html"), encoding="utf-8").read()
diagnosis = json.load(open(diagnosis_path))
context = json.load(open(os.path.join(directory, "data", "context.json")))
search = diagnosis["search"]
text = html.unescape(page)

def expect(condition, message):
    if not condition:
        sys.exit(f"{directory}: {message}")

def table(path):
    with open(os.path.join(directory, "data", path), newline="") as f:
        return list(csv.DictReader(f))

def close(a, b, what):
    expect(math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12), f"{what}: {a} != {b}")

# The extension of a calibration file as tofcomp writes it (yaml-cpp, block style): the
# "extension:" block as nested dicts and lists; scalars as numbers where they are.
def scalar(v):
    v = v.strip()
    if v.startswith("[") and v.endswith("]"):
        return [scalar(x) for x in v[1:-1].split(",")] if v[1:-1].strip() else []
    if v.startswith("{") and v.endswith("}"):
        pairs = (p.split(":", 1) for p in v[1:-1].split(","))
        return {k.strip(): scalar(x) for k, x in pairs}
    try:
        return float(v)
    except ValueError:
        return v.strip('"')

def block(lines, i, indent):
    """The block at `indent` from line i: a list (lines "- ...") or a dict; returns (value, i)."""
    if lines[i].lstrip().startswith("- "):
        items = []
        while i < len(lines) and lines[i].startswith(" " * indent + "- "):
            rest = lines[i][indent + 2:]
            if ":" in rest and not rest.startswith(("{", "[")):  # a map in the list
                lines[i] = " " * (indent + 2) + rest
                value, i = block(lines, i, indent + 2)
            else:
                value, i = scalar(rest), i + 1
            items.append(value)
        return items, i
    out = {}
    while (i < len(lines) and lines[i].startswith(" " * indent)
           and lines[i][indent] not in " -"):
        key, _, rest = lines[i].strip().partition(":")
        if rest.strip():
            out[key], i = scalar(rest), i + 1
        else:
            deeper = len(lines[i + 1]) - len(lines[i + 1].lstrip())
            out[key], i = block(lines, i + 1, deeper)
    return out, i

def read_extension(path):
    lines = [l.rstrip() for l in open(path, encoding="utf-8")
             if l.strip() and not l.lstrip().startswith("#")]
    start = lines.index("extension:")
    deeper = len(lines[start + 1]) - len(lines[start + 1].lstrip())
    return block(lines, start + 1, deeper)[0]

# Every PNG the page names exists, is a PNG, is not trivial; every PNG drawn is named.
sources = re.findall(r'<img src="([^"]+)"', page)
expect(sources, "names no figure")
for source in sources:
    expect(not re.match(r"[a-z]+:", source) and not source.startswith("/"),
           f"{source} is not a relative path")
    path = os.path.join(directory, source)
    expect(os.path.isfile(path), f"{source} is named but missing")
    with open(path, "rb") as f:
        expect(f.read(8) == b"\x89PNG\r\n\x1a\n", f"{source} is not a PNG")
    expect(os.path.getsize(path) > 10_000, f"{source} has only {os.path.getsize(path)} bytes")
drawn = {os.path.join("figures", f) for f in os.listdir(os.path.join(directory, "figures"))}
expect(drawn == set(sources), f"drawn but not named: {sorted(drawn - set(sources))}")

# Self-contained: no script, no external style sheet, nothing from the network.
expect("<script" not in page and "<link" not in page, "loads a script or a style sheet")
expect(not re.search(r'(src|href)="(https?:)?//', page), "refers to the network")

# The headline first: before any other section, what was kept and the numbers of the JSON.
headline = re.search(r'<div class="summary" id="headline">(.*?)</div>', page, re.S)
expect(headline, "no headline")
expect(page.index('id="headline"') < page.index("<h2"), "the headline is not first")
head_text = html.unescape(re.sub(r"<[^>]+>", "", headline.group(1)))
kept = search["kept"]
if kept:
    expect(f"The model search kept {', '.join(k['effect'] for k in kept)} (" in head_text,
           "the headline does not name what was kept")
else:
    expect("The model search kept nothing" in head_text,
           "the headline does not say nothing was kept")
windows = sorted(search["mae_mm"]["base"], key=int)
expect(windows, "the search has no held-out windows")
for w in windows:
    row = re.search(rf'<tr><td>{w}</td>(.*?)</tr>', headline.group(1))
    expect(row, f"headline: no row for window {w}")
    cells = re.findall(r"<td>([^<]*)</td>", row.group(1))
    wanted = [format(search["mae_mm"]["base"][w], ".3f"),
              format(search["mae_mm"]["final"][w], ".3f"),
              format(search["mae_factor"][w], ".2f"), format(search["cramer_rao_mae_mm"][w], ".3f"),
              format(search["mae_over_cramer_rao"]["base"][w], ".2f"),
              format(search["mae_over_cramer_rao"]["final"][w], ".2f")]
    expect(cells == wanted, f"headline, window {w}: {cells} where the JSON says {wanted}")
    close(search["mae_factor"][w], search["mae_mm"]["base"][w] / search["mae_mm"]["final"][w],
          f"the MAE factor of window {w}")
# The windows longer than the held-out blocks are said to be not compared, as the JSON lists them.
not_compared = search["windows_not_compared"]
expect(sorted(not_compared + [int(w) for w in windows]) == [200, 400, 800],
       f"compared {windows} and not {not_compared}: not the default windows")
said = re.search(r"Not compared: window ([0-9, ]+), longer than this record's held-out blocks "
                 r"\(([0-9]+) ranges\)", head_text)
if not_compared:
    expect(said and said.group(1) == ", ".join(map(str, not_compared))
           and int(said.group(2)) == search["block"], f"headline on windows not compared: {head_text!r}")
else:
    expect(not said, "the headline lists windows not compared where the JSON lists none")

# The paper's figures, each in a caption of its own; Fig. 4 on a logarithmic colour scale.
for number in figures_expected:
    expect(f"<b>Fig. {number}</b>" in page, f"Fig. {number} is missing")
expect(os.path.isfile(os.path.join(directory, "figures", "fig04_bias_temperature.png")),
       "no Fig. 4")
expect(re.search(r"<b>Fig. 4</b>[^<]*logarithmic colour scale", page),
       "Fig. 4 is not on a log scale")
expect(re.search(r"<b>Fig. 8</b>[^<]*on its own axis", page),
       "Fig. 8's error has no axis of its own")

# Each term of the search's figures: the kept ones with the values the calibration file holds.
terms = context["search_terms"]
extension = read_extension(calibration_path) if kept else None
expect([t["effect"] for t in terms if t["kept"]] == [k["effect"] for k in kept],
       "the kept terms' figures are not the search's kept terms")
for t in terms:
    figure = re.search(rf'<figure id="term-{t["index"]}" class="term (kept|not-kept)"><img '
                       r'src="([^"]+)"[^>]*><figcaption>(.*?)</figcaption></figure>', page, re.S)
    expect(figure, f"term {t['index']} ({t['effect']}): no figure")
    status, source, caption = figure.groups()
    caption = html.unescape(re.sub(r"<[^>]+>", "", caption))
    expect(source in sources, f"term {t['index']}: {source} is not named")
    expect(t["effect"] in caption, f"term {t['index']}: its caption names no effect")
    if not t["kept"]:
        expect(status == "not-kept" and "NOT KEPT" in caption and "no fitted effect" in caption,
               f"candidate {t['effect']}: its caption does not say it was not kept")
        expect(t["fitted"] is None and "curve" not in t["files"],
               f"candidate {t['effect']}: fitted values drawn for a candidate not kept")
        continue
    expect(status == "kept" and f"Kept at step {t['step']}" in caption,
           f"term {t['effect']}: its caption does not say it was kept")
    fitted = t["fitted"]
    if t["figure"] == "curve":
        same = [x for x in extension["terms"] if x["parameter"] == t["parameter"]
                and x["covariate"] == t["covariate"] and x["form"] == t["form"]
                and x.get("mode") == t.get("mode")]
        expect(len(same) == 1, f"term {t['effect']}: not once in {calibration_path}")
        stored = same[0]
        for a, b in zip(fitted["coefficients_mm"], stored["coefficients_mm"], strict=True):
            close(a, b, f"{t['effect']}: a coefficient")
        for key in ("time_constant_s", "centre", "scale"):
            if key in stored:
                close(fitted[key], stored[key], f"{t['effect']}: {key}")
        expect(format(stored["coefficients_mm"][0], ".4g") in caption,
               f"term {t['effect']}: the caption lacks the fitted coefficient")
        # The term the stored values give (core/effect_grammar.hpp's forms), computed here.
        gamma = stored["coefficients_mm"][0]
        if t["form"] == "linear":
            f = lambda c: gamma * (c - stored["centre"]) / stored["scale"]
        elif t["form"] == "decay":
            f = lambda c: gamma * math.exp(-max(c, 0.0) / stored["time_constant_s"])
        else:  # smooth: hats on the knots, the first left out: through 0, γ_1, γ_2, ...
            knots, at_knots = stored["knots"], [0.0] + stored["coefficients_mm"]
            def f(c):
                x = min(max(c, knots[0]), knots[-1])
                j = next(j for j in range(1, len(knots)) if x <= knots[j])
                share = (x - knots[j - 1]) / (knots[j] - knots[j - 1])
                return at_knots[j - 1] + share * (at_knots[j] - at_knots[j - 1])
        curve = table(t["files"]["curve"])
        expect(len(curve) >= 100, f"term {t['effect']}: a curve of {len(curve)} points")
        for point in curve:
            c, y = float(point["covariate"]), float(point["fitted_mm"])
            expect(abs(y - f(c)) <= 1e-9 * max(1.0, abs(y)),
                   f"term {t['effect']}: the curve at {c} is {y}, the calibration gives {f(c)}")
        ranges = table(t["files"]["ranges"])
        expect(sum(r["in_term"] == "1" for r in ranges) > 0.9 * len(ranges),
               f"term {t['effect']}: the partial residual is missing")
    elif t["figure"] == "bins":
        key = "spread_bins" if t["parameter"] == "spread" else "weight_bins"
        values = "variances_mm2" if t["parameter"] == "spread" else "weights"
        for a, b in zip(fitted["edges"], extension[key]["edges"], strict=True):
            close(a, b, f"{t['effect']}: an edge")
        for ra, rb in zip(fitted[values], extension[key][values], strict=True):
            for a, b in zip(ra, rb, strict=True):
                close(a, b, f"{t['effect']}: a bin's value")
    elif t["parameter"] == "markov":
        for ra, rb in zip(fitted["transition"], extension["transition"], strict=True):
            for a, b in zip(ra, rb, strict=True):
                close(a, b, f"{t['effect']}: a transition")
    elif t["parameter"] == "outliers":
        close(fitted["outlier_weight"], extension["outlier_weight"], "the outlier weight")

# The residual tests as evidence: one figure each, in the JSON's order, captioned "Evidence" with
# the test's numbers (the renderer's formats: .4g, .3g) and the search's verdict.
findings = diagnosis.get("findings", [])
findings_table = re.search(r'<table id="findings">(.*?)</table>', page, re.S)
expect(findings_table or not findings, "no table of the residual tests")
figures_of_findings = re.findall(r'<figure id="finding-([a-z0-9-]+)" class="finding">', page)
expect(len(figures_of_findings) == len(findings),
       f"{len(figures_of_findings)} finding figures for {len(findings)} findings")
for finding, shown in zip(findings, figures_of_findings):
    slug = re.sub(r"[^a-z0-9]+", "-", finding["effect"].lower()).strip("-")
    expect(shown == slug, f"finding figure {shown} where {slug} was expected")
    row = re.search(r"<tr[^>]*><td class=\"text\">" + re.escape(html.escape(finding["effect"]))
                    + r"</td>(.*?)</tr>", findings_table.group(1))
    expect(row, f"no row for the finding {finding['effect']}")
    for value in (format(finding["statistic"], ".4g"), format(finding["p_value"], ".3g")):
        expect(f"<td>{value}</td>" in row.group(1), f"{finding['effect']}: {value} not in its row")
    figure = re.search(rf'<figure id="finding-{slug}" class="finding"><img src="([^"]+)"[^>]*>'
                       r"<figcaption>(.*?)</figcaption></figure>", page, re.S)
    expect(figure, f"{finding['effect']}: no figure with a caption")
    source, caption = figure.groups()
    caption = html.unescape(re.sub(r"<[^>]+>", "", caption))
    expect(source.startswith("figures/finding_"),
           f"{finding['effect']}: {source} is not its figure")
    expect(caption.startswith(f"Evidence: {finding['effect']}."),
           f"{finding['effect']}: not captioned as evidence")
    numbers = (f" {format(finding['statistic'], '.4g')} (",
               f"p-value {format(finding['p_value'], '.3g')} against {finding['reference']} (its "
               f"textbook law: {format(finding['textbook_p_value'], '.3g')}), "
               + ("significant" if finding["significant"] else "not significant"))
    for part in numbers:
        expect(part in caption, f"{finding['effect']}: '{part}' not in its figure's caption")
    effect = finding["search_effect"]
    if effect in [k["effect"] for k in kept]:
        expect(f"The search kept {effect}" in caption, f"{finding['effect']}: the search's verdict")
    elif effect is not None:
        expect(f"The search's verdict on {effect}: " in caption,
               f"{finding['effect']}: the search's verdict is missing")

# The error of the paper's model before and after the compensation, the mean of y − Hθ̂ centred.
for window in (200, 400, 800):
    expect(re.search(rf"<tr><td>{window}</td><td class=\"text\">d̂ \(EM testing\)", text),
           f"no compensation row for window {window}")
expect("mean of y − Hθ̂ − Σπ̂ᵢμ̂ᵢ" in text, "the mean of y − Hθ̂ is not the centred one")
print(f"{directory}: {len(sources)} figures ({len(terms)} of the search's terms, {len(findings)} "
      f"of the residual tests), the headline, the terms and the evidence check out")
PY

all_figures=3,4,8,9,10,11,12,13,14,15,16,17,18,19
python3 "$work/check_report.py" "$work/report" "$work/diagnosis.json" "$all_figures" \
  "$work/calibration.yaml"
cmp <(python3 -m json.tool --sort-keys "$work/diagnosis.json") \
    <(python3 -m json.tool --sort-keys "$work/report/data/diagnosis.json")
# The evidence figures are drawn on what the tests ran on: every range of the record, under the
# model trained on all of it (not the report's first half); the terms' figures on every range
# under the final calibration, which is not the trained one.
python3 - "$work/drift.csv" "$work/report/data" <<'PY'
import csv, json, sys
with open(sys.argv[1]) as f:
    rows = csv.DictReader(line for line in f if not line.startswith("#"))
    ranges = sum(1 for r in rows if r["range_mm"])
for name in ("diagnosis_samples.csv", "search_residuals.csv"):
    with open(f"{sys.argv[2]}/{name}") as f:
        assert sum(1 for _ in f) - 1 == ranges, name
context = json.load(open(f"{sys.argv[2]}/context.json"))
assert context["diagnosis_calibration"] != context["calibration"], "the same model as the report's"
assert context["search_calibration"] != context["diagnosis_calibration"], "no term in the model"
PY
# On these data the search keeps the drift and names a second candidate it does not keep, so
# that the page above showed both kinds of term figure.
python3 - "$work/diagnosis.json" "$work/report/data/context.json" <<'PY'
import json, sys
d, c = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
# The time drift the scenario carries is named and kept first; a later step may keep more (with
# the search's fits converged, a warm-up decay passes on this record: it lowers d hat's held-out
# error). Each kept term has its figure, and the candidate named last and not kept one more.
kept = d["search"]["kept"]
assert d["named"].split(", ")[0] == "time drift" and kept, d
assert kept[0]["effect"] == "time drift", kept
assert [t["kept"] for t in c["search_terms"]] == [True] * len(kept) + [False], c["search_terms"]
assert len(d["findings"]) == 9, d  # so the page above carries all nine evidence figures
PY

# The renderer alone on a search that kept nothing (its one step named a candidate it did not
# keep, so no term was fitted): the headline says so, the MAE is the trained model's.
mkdir -p "$work/none"
cp -r "$work/report/data" "$work/none/data"
python3 - "$work/none/data" <<'PY'
import json, sys
path = sys.argv[1]
d = json.load(open(f"{path}/diagnosis.json"))
s = d["search"]
s["steps"] = s["steps"][:1]
s["steps"][0]["kept"] = False
s["kept"] = []
s["mae_mm"]["final"] = dict(s["mae_mm"]["base"])
s["mae_factor"] = {w: 1.0 for w in s["mae_factor"]}
s["mae_over_cramer_rao"]["final"] = dict(s["mae_over_cramer_rao"]["base"])
d["named"] = "none"
json.dump(d, open(f"{path}/diagnosis.json", "w"))
c = json.load(open(f"{path}/context.json"))
c["search_terms"] = []
json.dump(c, open(f"{path}/context.json", "w"))
PY
"$python" "$renderer" --quiet "$work/none"
python3 "$work/check_report.py" "$work/none" "$work/none/data/diagnosis.json" "$all_figures" -
grep -q "The model search kept <b>nothing</b>" "$work/none/index.html"
if ls "$work/none/figures" | grep -q "^term"; then echo "a term figure without a term"; exit 1; fi

# A report directory that cannot be made: exit 1, the directory named, before the search's
# long work (a few seconds, where the search takes a minute).
touch "$work/a-file"
SECONDS=0
set +e
"$tofcomp" -q diagnose "$work/drift.csv" --datasheet "$datasheet" --report "$work/a-file/report" \
  > /dev/null 2> "$work/err"
rc=$?
set -e
test "$rc" -eq 1 || { echo "bad DIR: exit $rc"; cat "$work/err"; exit 1; }
grep -q "report directory $work/a-file/report: cannot create it" "$work/err" \
  || { cat "$work/err"; exit 1; }
test "$SECONDS" -le 10 || { echo "bad DIR: found after $SECONDS s"; exit 1; }

# A Python without matplotlib: exit 1, naming what is missing and how to install it.
mkdir -p "$work/hidden"
echo 'raise ImportError("hidden by the test")' > "$work/hidden/matplotlib.py"
printf '#!/bin/sh\nPYTHONPATH=%s exec %s "$@"\n' "$work/hidden" "$(command -v "$python")" \
  > "$work/python-without-matplotlib"
chmod +x "$work/python-without-matplotlib"
SECONDS=0
set +e
TOFCOMP_PYTHON="$work/python-without-matplotlib" "$tofcomp" -q diagnose "$work/drift.csv" \
  --datasheet "$datasheet" --report "$work/report2" > /dev/null 2> "$work/err"
rc=$?
set -e
test "$rc" -eq 1 || { echo "no matplotlib: exit $rc"; cat "$work/err"; exit 1; }
grep -q "lacks the Python module(s) matplotlib (Debian package python3-matplotlib)" "$work/err" \
  || { cat "$work/err"; exit 1; }
grep -q "apt-get install python3 python3-matplotlib python3-numpy" "$work/err" \
  || { cat "$work/err"; exit 1; }
test "$SECONDS" -le 10 || { echo "no matplotlib: found after $SECONDS s"; exit 1; }
echo "diagnose report test passed"
