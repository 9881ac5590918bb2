#!/usr/bin/env bash
# End to end through the real binary: `tofcomp diagnose --report DIR` on a short time-drift
# scenario, then checks on the report: index.html names only PNGs that exist, are PNG and are
# not trivial, and no PNG goes unnamed; every paper figure the report promises appears; the
# findings and the before/after errors carry the numbers `--json` printed; each finding has its
# figure, captioned with its statistic and p-value; nothing is fetched from the network. Then
# the renderer alone on the diagnosis JSON's new shape (extension.errors per window) and on a
# diagnosis that names nothing; then the errors a user meets: a DIR that cannot be made, a
# Python without matplotlib.
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
  > "$work/diagnosis.json"

# The checks of one rendered report; argv: report dir, diagnosis JSON, expected figures.
cat > "$work/check_report.py" <<'PY'
import html, json, os, re, sys

directory, diagnosis_path = sys.argv[1], sys.argv[2]
figures_expected = sys.argv[3].split(",")
page = open(os.path.join(directory, "index.html"), encoding="utf-8").read()
diagnosis = json.load(open(diagnosis_path))
text = html.unescape(page)

def expect(condition, message):
    if not condition:
        sys.exit(f"{directory}: {message}")

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

# The paper's figures, each in a caption of its own.
for number in figures_expected:
    expect(f"<b>Fig. {number}</b>" in page, f"Fig. {number} is missing")

# The findings with the numbers of --json (the renderer's formats: .4g, .3g).
for finding in diagnosis.get("findings", []):
    row = re.search(r"<tr[^>]*><td class=\"text\">" + re.escape(html.escape(finding["effect"]))
                    + r"</td>(.*?)</tr>", page)
    expect(row, f"no row for the finding {finding['effect']}")
    cells = row.group(1)
    for value in (format(finding["statistic"], ".4g"), format(finding["p_value"], ".3g")):
        expect(f"<td>{value}</td>" in cells, f"{finding['effect']}: {value} not in its row")
    expect(("<td>yes</td>" if finding["significant"] else "<td>no</td>") in cells,
           f"{finding['effect']}: significance not shown")

# One figure per finding of the JSON, in the findings' order: a PNG the page names (so checked
# above: it exists, is a PNG of more than 10 kB), its caption carrying the finding's numbers.
figures_of_findings = re.findall(r'<figure id="finding-([a-z0-9-]+)" class="finding">', page)
findings = diagnosis.get("findings", [])
expect(len(figures_of_findings) == len(findings),
       f"{len(figures_of_findings)} finding figures for {len(findings)} findings")
for finding, shown in zip(findings, figures_of_findings):
    slug = re.sub(r"[^a-z0-9]+", "-", finding["effect"].lower()).strip("-")
    expect(shown == slug, f"finding figure {shown} where {slug} was expected")
    figure = re.search(rf'<figure id="finding-{slug}" class="finding"><img src="([^"]+)"[^>]*>'
                       r"<figcaption>(.*?)</figcaption></figure>", page, re.S)
    expect(figure, f"{finding['effect']}: no figure with a caption")
    source, caption = figure.groups()
    expect(source in sources and source.startswith("figures/finding_"),
           f"{finding['effect']}: the figure {source} is not a finding figure the page names")
    expect(html.escape(finding["effect"]) in caption, f"{source}: its caption names no effect")
    numbers = (f" {format(finding['statistic'], '.4g')}, "
               f"p-value {format(finding['p_value'], '.3g')}, "
               + ("significant" if finding["significant"] else "not significant"))
    expect(numbers in caption, f"{finding['effect']}: '{numbers}' not in its figure's caption")

# The extension and its error table: MAE before and after of each window, and the factor.
extension = diagnosis.get("extension")
if extension is None:
    expect("None kept" in text, "says nothing of the extension")
else:
    expect(("; kept." if extension["kept"] else "not kept") in text, "the verdict is missing")
    rows = extension.get("errors") or [{
        "window": extension["window"],
        "before": {"mean_absolute_error_mm": extension["held_out_mae_before_mm"]},
        "after": {"mean_absolute_error_mm": extension["held_out_mae_after_mm"]},
        "mae_factor": extension["held_out_mae_before_mm"] / extension["held_out_mae_after_mm"]}]
    for r in rows:
        row = re.search(rf"<tr><td>{r['window']}</td>(.*?)</tr>", page)
        expect(row, f"no error row for window {r['window']}")
        for value in (format(r["before"]["mean_absolute_error_mm"], ".3f"),
                      format(r["after"]["mean_absolute_error_mm"], ".3f"),
                      format(r["mae_factor"], ".2f")):
            expect(f"<td>{value}</td>" in row.group(1), f"window {r['window']}: {value} missing")
    for name, value in (extension.get("parameters") or {}).items():
        expect(name in text and format(value, ".4g") in text, f"parameter {name} missing")

# The error before and after the compensation, per window length of the report.
for window in (200, 400, 800):
    expect(re.search(rf"<tr><td>{window}</td><td class=\"text\">d̂ \(EM testing\)", text),
           f"no compensation row for window {window}")
print(f"{directory}: {len(sources)} figures ({len(findings)} of findings), the findings and the "
      f"errors check out")
PY

all_figures=3,4,8,9,10,11,12,13,14,15,16,17,18,19
python3 "$work/check_report.py" "$work/report" "$work/diagnosis.json" "$all_figures"
cmp <(python3 -m json.tool --sort-keys "$work/diagnosis.json") \
    <(python3 -m json.tool --sort-keys "$work/report/data/diagnosis.json")
# The findings' figures are drawn on what the tests ran on: every range of the record, under
# the calibration the diagnosis trained on all of it (not the report's first half).
python3 - "$work/drift.csv" "$work/report/data" <<'PY'
import csv, json, sys
with open(sys.argv[1]) as f:
    rows = csv.DictReader(line for line in f if not line.startswith("#"))
    ranges = sum(1 for r in rows if r["range_mm"])
with open(f"{sys.argv[2]}/diagnosis_samples.csv") as f:
    tested = sum(1 for _ in f) - 1
assert tested == ranges, (tested, ranges)
context = json.load(open(f"{sys.argv[2]}/context.json"))
assert context["diagnosis_calibration"] != context["calibration"], "the same model as the report's"
PY
python3 - "$work/diagnosis.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
# The time drift the scenario carries is named first; a later step may keep more (with the
# search's fits converged, a warm-up decay passes on this record: it lowers d hat's held-out error).
# (The kept terms are under "search" since the model search of issue 14; "extension" was gone.)
assert d["named"].split(", ")[0] == "time drift" and d["search"]["kept"], d
assert d["search"]["kept"][0]["effect"] == "time drift", d["search"]["kept"]
assert len(d["findings"]) == 9, d  # so the page above carries all nine finding figures
PY

# The renderer alone on the shape the diagnosis JSON is moving to, and on a diagnosis that
# names nothing.
for case in new-shape none; do
  mkdir -p "$work/$case"
  cp -r "$work/report/data" "$work/$case/data"
done
cp "$root/tests/cli/report-diagnosis-new-shape.json" "$work/new-shape/data/diagnosis.json"
printf '{"findings": [], "named": "none"}\n' > "$work/none/data/diagnosis.json"
for case in new-shape none; do
  "$python" "$renderer" --quiet "$work/$case"
  python3 "$work/check_report.py" "$work/$case" "$work/$case/data/diagnosis.json" "$all_figures"
done
grep -q "Held-out log-likelihood gain: 1234.5" "$work/new-shape/index.html"
grep -q "None kept: nothing is significant" "$work/none/index.html"

# A report directory that cannot be made: exit 1, the directory named.
touch "$work/a-file"
set +e
"$tofcomp" -q diagnose "$work/drift.csv" --datasheet "$datasheet" --report "$work/a-file/report" \
  > /dev/null 2> "$work/err"
rc=$?
set -e
test "$rc" -eq 1 || { echo "bad DIR: exit $rc"; cat "$work/err"; exit 1; }
grep -q "report directory $work/a-file/report: cannot create it" "$work/err" \
  || { cat "$work/err"; exit 1; }

# A Python without matplotlib: exit 1, naming what is missing and how to install it.
mkdir -p "$work/hidden"
echo 'raise ImportError("hidden by the test")' > "$work/hidden/matplotlib.py"
printf '#!/bin/sh\nPYTHONPATH=%s exec %s "$@"\n' "$work/hidden" "$(command -v "$python")" \
  > "$work/python-without-matplotlib"
chmod +x "$work/python-without-matplotlib"
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
echo "diagnose report test passed"
