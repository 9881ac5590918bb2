#!/usr/bin/env python3
"""Scores `tofcomp diagnose` on a blind suite made by generate.py.

Usage: score.py --tofcomp PATH --suite DIR [--jobs J] [--timeout S] [--json OUT.json]
                [--calibrations CDIR]

For every DIR/data/<id>.csv that has a truth DIR/truth/<id>.json it runs
    PATH diagnose DIR/data/<id>.csv --json -q [--calibration-output CDIR/<id>.yaml]
(and, for a set with an effect, the same on its clean counterpart), reads only the output contract
    search.kept        list of {parameter, covariate, ...}, in the order the effects were added
    search.best        {parameter, covariate, ...} of the top-ranked candidate, or null
    search.mae_mm.final / search.mae_mm.base   {"200": mm, "400": mm, "800": mm}
    search.windows_not_compared  (optional) windows left out of mae_mm (a short record's blocks)
    trained_model.modes  (optional) the lasing modes of the model the search started from
    search.steps[0].not_told_apart  (optional) candidates the data do not tell from the first named
    junction_recheck.chosen  (optional) which start a re-check of the junction kept, or null
    structure_recheck.chosen  (optional) "first" or "again": which structure a re-check kept, or null
    findings  (optional) the residual tests, evidence beside the search: [{effect, significant,
              textbook_p_value (optional)}], in the detector's ranking
and prints how the detector did.  A non-zero exit, a timeout, output that is not JSON or a missing
or malformed field is a failure of that run, listed with its stderr tail.  Exit status 0 once
everything that could be scored was (the figures are the result), 2 on bad arguments.

Only this script reads DIR/truth.  Pure standard library.
"""
import argparse
import glob
import json
import math
import os
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

from kinds import KINDS  # noqa: E402  (the vocabulary both scripts share)
SEP = "\u00d7"  # ×
LABELS = [p + SEP + c for p, c in KINDS]
ABBR = dict(zip(LABELS, ["B.time", "B.t_on", "B.rate", "B.amb", "MO.tj", "S.tj", "W.tj", "W.t_on",
                         "markov", "extra", "outl", "therm3"]))
WINDOWS = ("200", "400", "800")
RATIO_OK = 1.25
NOTHING = "nothing"
EXTRA_MODE = "extra_mode" + SEP + "none"
CLEAN = "clean"
# The residual tests (`findings`, evidence beside the search): the label each one looks for, by
# its `effect`; serial dependence is a symptom of any effect (no label). A test is significant by
# its `textbook_p_value` when that is below EVIDENCE_ALPHA / the number of tests (Bonferroni, as
# the detector states its own level).
EVIDENCE_LABELS = {
    "mode persistence": "markov" + SEP + "none",
    "temperature-dependent mode weights": "weights" + SEP + "junction_temperature",
    "temperature-dependent spread": "spread" + SEP + "junction_temperature",
    "outliers": "outliers" + SEP + "none",
    "heating hysteresis": "bias" + SEP + "heating_rate",
    "time drift": "bias" + SEP + "time",
    "warm-up after power-on": "bias" + SEP + "time_since_power_on",
    "one more lasing mode": EXTRA_MODE,
    "serial dependence": None,
}
EVIDENCE_ALPHA = 0.05


class ContractError(Exception):
    pass


def label_of(obj, where):
    if not isinstance(obj, dict):
        raise ContractError("%s is not an object" % where)
    p, c = obj.get("parameter"), obj.get("covariate")
    if not isinstance(p, str) or not isinstance(c, str):
        raise ContractError("%s lacks a string 'parameter' and 'covariate'" % where)
    return p + SEP + c


def number(v, where):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ContractError("%s is not a finite number (%r)" % (where, v))
    return float(v)


def parse_output(stdout):
    """The output contract -> {kept: [labels], best: label|None, final: {w: mm}, base: {w: mm}}."""
    try:
        doc = json.loads(stdout)
    except (ValueError, UnicodeDecodeError) as ex:
        head = stdout[:120].decode("utf-8", "replace") if isinstance(stdout, bytes) else stdout[:120]
        raise ContractError("output is not JSON (%s); starts %r" % (ex, head))
    if not isinstance(doc, dict) or not isinstance(doc.get("search"), dict):
        raise ContractError("missing field: search")
    s = doc["search"]
    if "kept" not in s:
        raise ContractError("missing field: search.kept")
    if not isinstance(s["kept"], list):
        raise ContractError("search.kept is not a list")
    kept = [label_of(k, "search.kept[%d]" % i) for i, k in enumerate(s["kept"])]
    if "best" not in s:
        raise ContractError("missing field: search.best")
    best = None if s["best"] is None else label_of(s["best"], "search.best")
    mae = s.get("mae_mm")
    if not isinstance(mae, dict):
        raise ContractError("missing field: search.mae_mm")
    out = {"kept": kept, "best": best, "modes": None, "alike": [], "recheck": None,
           "structure_recheck": None, "evidence": None}
    findings = doc.get("findings")
    if isinstance(findings, list) and findings:
        out["evidence"] = parse_findings(findings)
    recheck = doc.get("junction_recheck")
    if isinstance(recheck, dict) and isinstance(recheck.get("chosen"), str):
        out["recheck"] = recheck["chosen"]
    recheck = doc.get("structure_recheck")
    if isinstance(recheck, dict) and isinstance(recheck.get("chosen"), str):
        out["structure_recheck"] = recheck["chosen"]
    steps = s.get("steps")
    if isinstance(steps, list) and steps and isinstance(steps[0], dict) and "not_told_apart" in steps[0]:
        alike = steps[0]["not_told_apart"]
        if not isinstance(alike, list):
            raise ContractError("search.steps[0].not_told_apart is not a list")
        out["alike"] = [label_of(a, "search.steps[0].not_told_apart[%d]" % i) for i, a in enumerate(alike)]
    trained = doc.get("trained_model")
    if isinstance(trained, dict) and "modes" in trained:
        modes = trained["modes"]
        if isinstance(modes, bool) or not isinstance(modes, int) or modes < 1:
            raise ContractError("trained_model.modes is not a positive integer (%r)" % (modes,))
        out["modes"] = modes
    # A window the detector says it did not compare (longer than a short record's held-out
    # blocks) has no MAE: None, and no ratio.
    not_compared = s.get("windows_not_compared", [])
    if not isinstance(not_compared, list):
        raise ContractError("search.windows_not_compared is not a list")
    not_compared = {str(w) for w in not_compared}
    for part in ("final", "base"):
        m = mae.get(part)
        if not isinstance(m, dict):
            raise ContractError("missing field: search.mae_mm.%s" % part)
        vals = {}
        for w in WINDOWS:
            if w not in m:
                if w in not_compared:
                    vals[w] = None
                    continue
                raise ContractError("missing field: search.mae_mm.%s.%s" % (part, w))
            vals[w] = number(m[w], "search.mae_mm.%s.%s" % (part, w))
        out[part] = vals
    return out


def parse_findings(findings):
    """The residual tests -> [{label, significant, textbook_significant}] in the detector's order
    (label None for a test of no one effect; textbook_significant None without a textbook p)."""
    level = EVIDENCE_ALPHA / len(findings)
    out = []
    for i, f in enumerate(findings):
        if not isinstance(f, dict) or not isinstance(f.get("effect"), str):
            raise ContractError("findings[%d] has no effect" % i)
        if not isinstance(f.get("significant"), bool):
            raise ContractError("findings[%d].significant is not true or false" % i)
        textbook = f.get("textbook_p_value")
        out.append({"label": EVIDENCE_LABELS.get(f["effect"], "?" + f["effect"]),
                    "significant": f["significant"],
                    "textbook_significant": (number(textbook, "findings[%d].textbook_p_value" % i)
                                             < level if textbook is not None else None)})
    return out


_live = set()
_live_lock = threading.Lock()


def run_detector(cmd, csv, timeout, calibration=None):
    """Runs the detector on one file, writing the calibration it keeps to `calibration` when
    given.  Returns {ok, result | reason, stderr_tail, seconds}."""
    argv = cmd + ["diagnose", csv, "--json", "-q"]
    if calibration:
        argv += ["--calibration-output", calibration]
    t0 = time.time()
    try:
        proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                stdin=subprocess.DEVNULL, start_new_session=True)
    except OSError as ex:
        return {"ok": False, "reason": "could not start: %s" % ex, "stderr_tail": "",
                "seconds": 0.0, "exit": None}
    with _live_lock:
        _live.add(proc)
    timed_out = False
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # the detector we started, and its children
        except OSError:
            pass
        out, err = proc.communicate()
    finally:
        with _live_lock:
            _live.discard(proc)
    dt = time.time() - t0
    tail = err.decode("utf-8", "replace")[-2000:]
    tail = "\n".join(tail.splitlines()[-20:])
    if timed_out:
        return {"ok": False, "reason": "timeout after %g s" % timeout, "stderr_tail": tail,
                "seconds": dt, "exit": None}
    if proc.returncode != 0:
        return {"ok": False, "reason": "exit status %d" % proc.returncode, "stderr_tail": tail,
                "seconds": dt, "exit": proc.returncode}
    try:
        res = parse_output(out)
    except ContractError as ex:
        return {"ok": False, "reason": str(ex), "stderr_tail": tail, "seconds": dt, "exit": 0}
    return {"ok": True, "result": res, "stderr_tail": tail, "seconds": dt, "exit": 0}


def fmt_table(rows, header):
    widths = [max(len(str(r[i])) for r in rows + [header]) for i in range(len(header))]
    line = lambda r: "  ".join(str(v).rjust(w) if i else str(v).ljust(w)
                               for i, (v, w) in enumerate(zip(r, widths)))
    return "\n".join([line(header), line(["-" * w for w in widths])] + [line(r) for r in rows])


def ordered(labels):
    known = [l for l in LABELS if l in labels]
    return known + sorted(l for l in labels if l not in LABELS and l not in (NOTHING, CLEAN))


def main(argv=None):
    ap = argparse.ArgumentParser(description="Scores tofcomp diagnose on a blind suite.")
    ap.add_argument("--tofcomp", required=True,
                    help="the detector's executable (a command line is split like a shell would)")
    ap.add_argument("--suite", required=True, help="a directory made by generate.py")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per run (default 900)")
    ap.add_argument("--json", default=None, help="write the results here")
    ap.add_argument("--calibrations", default=None,
                    help="also write each run's calibration here as <data file>.yaml, for "
                         "replay_score.py (the daemon's path)")
    a = ap.parse_args(argv)
    if a.jobs < 1 or a.timeout <= 0:
        ap.error("--jobs must be >= 1 and --timeout > 0")
    cmd = shlex.split(a.tofcomp)
    if not cmd:
        ap.error("--tofcomp is empty")
    exe = cmd[0]
    if os.sep in exe:
        if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
            ap.error("--tofcomp %s is not an executable file" % exe)
        cmd[0] = os.path.abspath(exe)
    elif shutil.which(exe) is None:
        ap.error("--tofcomp %s is not found" % exe)
    if a.calibrations:
        os.makedirs(a.calibrations, exist_ok=True)
    tdir, ddir = os.path.join(a.suite, "truth"), os.path.join(a.suite, "data")
    if not os.path.isdir(tdir) or not os.path.isdir(ddir):
        ap.error("%s has no truth/ and data/" % a.suite)

    truths = []
    for p in sorted(glob.glob(os.path.join(tdir, "*.json"))):
        sid = os.path.basename(p)[:-5]
        csv = os.path.join(ddir, sid + ".csv")
        if not os.path.isfile(csv):
            continue
        with open(p) as f:
            tr = json.load(f)
        tr["_csv"] = csv
        cp = tr.get("counterpart")
        tr["_clean_csv"] = os.path.join(ddir, cp) if cp else None
        truths.append(tr)
    if not truths:
        ap.error("no data set with a truth in %s" % a.suite)

    tasks = []
    for tr in truths:
        tasks.append((tr["id"], "set", tr["_csv"]))
        if tr["_clean_csv"]:
            tasks.append((tr["id"], "counterpart", tr["_clean_csv"]))
    runs = {}
    done = [0]
    lock = threading.Lock()
    t_start = time.time()

    def work(task):
        sid, which, csv = task
        if not os.path.isfile(csv):
            r = {"ok": False, "reason": "file missing: %s" % csv, "stderr_tail": "", "seconds": 0.0,
                 "exit": None}
        else:
            calibration = (os.path.join(a.calibrations,
                                        os.path.basename(csv)[:-len(".csv")] + ".yaml")
                           if a.calibrations else None)
            r = run_detector(cmd, csv, a.timeout, calibration)
        with lock:
            runs[(sid, which)] = r
            done[0] += 1
            print("[%d/%d] %s %-11s %-5s %6.1fs%s" % (
                done[0], len(tasks), sid, which, "ok" if r["ok"] else "FAIL", r["seconds"],
                "" if r["ok"] else "  " + r["reason"]), file=sys.stderr, flush=True)
        return r

    try:
        with ThreadPoolExecutor(max_workers=a.jobs) as ex:
            list(ex.map(work, tasks))
    except KeyboardInterrupt:
        with _live_lock:
            for p in list(_live):
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except OSError:
                    pass
        raise

    report = evaluate(truths, runs)
    report.update({"tofcomp": a.tofcomp, "suite": os.path.abspath(a.suite),
                   "timeout_s": a.timeout, "jobs": a.jobs,
                   "wall_s": round(time.time() - t_start, 1)})
    print(render(report))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(report, f, indent=1)
    return 0


def evaluate(truths, runs):
    sets = []
    failures = []
    for tr in truths:
        sid = tr["id"]
        labels = [e["parameter"] + SEP + e["covariate"] for e in tr.get("effects", [])]
        r = runs[(sid, "set")]
        rc = runs.get((sid, "counterpart"))
        row = {"id": sid, "kind": tr["kind"], "true": labels,
               "strength": [e.get("strength") for e in tr.get("effects", [])],
               "ok": r["ok"], "seconds": round(r["seconds"], 1)}
        if not r["ok"]:
            failures.append({"id": sid, "run": "set", "reason": r["reason"],
                             "exit": r["exit"], "stderr_tail": r["stderr_tail"]})
        else:
            res = r["result"]
            row.update({"kept": res["kept"], "best": res["best"],
                        "first": res["kept"][0] if res["kept"] else NOTHING,
                        "mae_final": res["final"], "mae_base": res["base"],
                        "modes": res["modes"], "alike": res["alike"],
                        "recheck": res["recheck"],
                        "structure_recheck": res["structure_recheck"],
                        "evidence": res["evidence"]})
        if rc is not None:
            row["counterpart_ok"] = rc["ok"]
            if not rc["ok"]:
                failures.append({"id": sid + "-clean", "run": "counterpart", "reason": rc["reason"],
                                 "exit": rc["exit"], "stderr_tail": rc["stderr_tail"]})
            else:
                row.update({"counterpart_kept": rc["result"]["kept"],
                            "counterpart_modes": rc["result"]["modes"],
                            "counterpart_recheck": rc["result"]["recheck"],
                            "counterpart_structure_recheck": rc["result"]["structure_recheck"],
                            "counterpart_mae_final": rc["result"]["final"],
                            "counterpart_evidence": rc["result"]["evidence"],
                            "counterpart_mae_base": rc["result"]["base"]})
        if r["ok"] and rc is not None and rc["ok"]:
            row["mae_ratio"] = {w: (row["mae_final"][w] / row["counterpart_mae_final"][w]
                                    if row["mae_final"][w] is not None
                                    and row["counterpart_mae_final"][w] is not None
                                    and row["counterpart_mae_final"][w] > 0 else None)
                                for w in WINDOWS}
        sets.append(row)

    singles = [s for s in sets if s["kind"] == "single"]
    cleans = [s for s in sets if s["kind"] == "clean"]
    pairs = [s for s in sets if s["kind"] == "pair"]

    # confusion: true label (or clean) x first kept label (or nothing), scored sets only
    confusion = {}
    for s in singles + cleans:
        if not s["ok"]:
            continue
        t = s["true"][0] if s["kind"] == "single" else CLEAN
        confusion.setdefault(t, {})
        confusion[t][s["first"]] = confusion[t].get(s["first"], 0) + 1

    per_kind = {}
    for s in singles:
        t = s["true"][0]
        k = per_kind.setdefault(t, {"n": 0, "failed": 0, "named_right_first": 0,
                                    "named_anywhere": 0, "best_right": 0, "nothing": 0,
                                    "right_or_alike": 0})
        if not s["ok"]:
            k["failed"] += 1
            continue
        k["n"] += 1
        s["named_right"] = s["first"] == t
        k["named_right_first"] += s["named_right"]
        k["named_anywhere"] += t in s["kept"]
        k["best_right"] += s["best"] == t
        # Named right first, or the first step's named (kept or not) is the truth, or the data do
        # not tell the truth from it.
        k["right_or_alike"] += s["named_right"] or s["best"] == t or t in s.get("alike", [])
        k["nothing"] += not s["kept"]
    per_kind = {l: per_kind[l] for l in ordered(list(per_kind))}

    clean = {"n": sum(1 for s in cleans if s["ok"]), "failed": sum(1 for s in cleans if not s["ok"]),
             "nothing_kept": sum(1 for s in cleans if s["ok"] and not s["kept"])}
    # counterparts are clean data too: report them apart (they are the same draws as the effect sets)
    cps = [s for s in sets if "counterpart_kept" in s]
    counterparts = {"n": len(cps), "nothing_kept": sum(1 for s in cps if not s["counterpart_kept"])}

    pair_rows = []
    for s in pairs:
        if not s["ok"]:
            continue
        both = all(t in s["kept"] for t in s["true"])
        one = any(t in s["kept"] for t in s["true"])
        s["both_kept"] = both
        pair_rows.append({"id": s["id"], "true": s["true"], "kept": s["kept"], "both": both,
                          "at_least_one": one})
    pair_sum = {"n": len(pair_rows), "failed": sum(1 for s in pairs if not s["ok"]),
                "both": sum(r["both"] for r in pair_rows),
                "at_least_one": sum(r["at_least_one"] for r in pair_rows), "rows": pair_rows}

    tert = []
    for i, (lo, hi) in enumerate([(0, 1 / 3), (1 / 3, 2 / 3), (2 / 3, 1.0001)]):
        sel = [s for s in singles if s["ok"] and lo <= s["strength"][0] < hi]
        tert.append({"tertile": i + 1, "strength": [round(lo, 3), round(min(hi, 1), 3)],
                     "n": len(sel), "named_right_first": sum(s["named_right"] for s in sel)})

    ratio_rows = []
    for s in singles:
        if s.get("named_right") and "mae_ratio" in s:
            ratio_rows.append({"id": s["id"], "true": s["true"][0], "ratio": s["mae_ratio"],
                               "final": s["mae_final"], "counterpart_final": s["counterpart_mae_final"]})
    ratio_ok = {}
    for w in WINDOWS:
        vals = [r["ratio"][w] for r in ratio_rows if r["ratio"][w] is not None]
        ratio_ok[w] = {"n": len(vals), "le_%g" % RATIO_OK: sum(v <= RATIO_OK for v in vals)}
    all_ok = sum(all(r["ratio"][w] is not None and r["ratio"][w] <= RATIO_OK for w in WINDOWS)
                 for r in ratio_rows)
    named_right_no_ratio = [s["id"] for s in singles if s.get("named_right") and "mae_ratio" not in s]

    # An extra lasing mode may be taken in by the structure the detector chose from the data (its
    # trained model has more modes than on the clean counterpart) instead of being kept as a
    # term: reported apart, never counted as named, with the same comparison on the other effect
    # sets as its false-alarm rate.
    took_in = {"extra": [], "other": []}
    for s in singles + pairs:
        if s.get("modes") is None or s.get("counterpart_modes") is None:
            continue
        group = "extra" if EXTRA_MODE in s["true"] else "other"
        took_in[group].append({"id": s["id"], "true": s["true"], "modes": s["modes"],
                               "counterpart_modes": s["counterpart_modes"],
                               "more": s["modes"] > s["counterpart_modes"],
                               "named": EXTRA_MODE in s.get("kept", [])})

    evidence = evaluate_evidence(singles, cleans, cps)

    return {"sets": sets, "confusion": confusion, "per_kind": per_kind, "clean": clean,
            "evidence": evidence,
            "counterparts": counterparts, "pairs": pair_sum, "strength_tertiles": tert,
            "structure_took_in": took_in,
            "junction_recheck": {
                "runs": sum(1 for s in sets if s.get("recheck")) +
                        sum(1 for s in sets if s.get("counterpart_recheck")),
                "case_log_chosen": sum(1 for s in sets if s.get("recheck") == "case_log") +
                                   sum(1 for s in sets if s.get("counterpart_recheck") == "case_log"),
                "scored_runs": sum(1 for s in sets if s["ok"]) +
                               sum(1 for s in sets if s.get("counterpart_ok"))},
            "structure_recheck": {
                "runs": sum(1 for s in sets if s.get("structure_recheck")) +
                        sum(1 for s in sets if s.get("counterpart_structure_recheck")),
                "chosen_again": sum(1 for s in sets if s.get("structure_recheck") == "again") +
                                sum(1 for s in sets
                                    if s.get("counterpart_structure_recheck") == "again"),
                "scored_runs": sum(1 for s in sets if s["ok"]) +
                               sum(1 for s in sets if s.get("counterpart_ok"))},
            "mae_ratio": {"threshold": RATIO_OK, "rows": ratio_rows, "per_window": ratio_ok,
                          "all_windows_ok": all_ok, "n": len(ratio_rows),
                          "named_right_without_counterpart": named_right_no_ratio},
            "failures": failures,
            "totals": {"sets": len(sets), "singles": len(singles), "clean": len(cleans),
                       "pairs": len(pairs), "runs_failed": len(failures)}}


def evaluate_evidence(singles, cleans, counterparts):
    """The residual tests, by the detector's reference and by the textbook's: on records without
    an effect, how many raise any test; on single-effect sets, how often the test of the true
    effect is significant and first among the significant. None when no run reported findings."""
    def first(ev, key):
        hits = [f["label"] for f in ev if f[key]]
        return (hits[0] or "serial dependence") if hits else NOTHING

    runs_clean = [s["evidence"] for s in cleans if s["ok"] and s.get("evidence")]
    runs_clean += [s["counterpart_evidence"] for s in counterparts if s.get("counterpart_evidence")]
    scored = [s for s in singles if s["ok"] and s.get("evidence")]
    if not runs_clean and not scored:
        return None
    out = {"clean_runs": len(runs_clean), "per_kind": {}, "confusion": {}}
    for key in ("significant", "textbook_significant"):
        usable = [ev for ev in runs_clean if all(f[key] is not None for f in ev)]
        out["clean_any_" + key] = [sum(any(f[key] for f in ev) for ev in usable), len(usable)]
    for s in scored:
        t = s["true"][0]
        k = out["per_kind"].setdefault(t, {"n": 0, "has_test": False, "significant": 0,
                                           "first": 0, "textbook_significant": 0,
                                           "textbook_first": 0})
        k["n"] += 1
        own = [f for f in s["evidence"] if f["label"] == t]
        k["has_test"] = bool(own)
        for key in ("significant", "textbook_significant"):
            prefix = "" if key == "significant" else "textbook_"
            k[prefix + "significant"] += bool(own and own[0][key])
            k[prefix + "first"] += first(s["evidence"], key) == t
        row = out["confusion"].setdefault(t, {})
        f1 = first(s["evidence"], "significant")
        row[f1] = row.get(f1, 0) + 1
    out["per_kind"] = {l: out["per_kind"][l] for l in ordered(list(out["per_kind"]))}
    return out


def render_evidence(ev):
    out = ["\nEvidence: the residual tests (findings), judged by the detector's reference and by "
           "their textbook laws"]
    for key, name in (("significant", "the detector's"), ("textbook_significant", "textbook")):
        hit, n = ev["clean_any_" + key]
        out.append("  records without an effect (clean sets and counterparts) raising any test, "
                   "%s: %d/%d" % (name, hit, n))
    tab = []
    for l, k in ev["per_kind"].items():
        if not k["has_test"]:
            tab.append([l, k["n"], "no test", "", "", ""])
            continue
        tab.append([l, k["n"], "%d/%d" % (k["significant"], k["n"]), "%d/%d" % (k["first"], k["n"]),
                    "%d/%d" % (k["textbook_significant"], k["n"]),
                    "%d/%d" % (k["textbook_first"], k["n"])])
    out.append(fmt_table(tab, ["kind", "n", "own test significant", "first significant",
                               "textbook: significant", "textbook: first"]))
    conf = ev["confusion"]
    cols = sorted({c for r in conf.values() for c in r}, key=str)
    out.append("  first significant test (detector's reference), rows the true label:")
    out.append(fmt_table([[r] + [conf[r].get(c, "") or "." for c in cols] for r in ordered(list(conf))],
                         ["true \\ first"] + [ABBR.get(c, c) for c in cols]))
    return out


def render(rep):
    out = []
    T = rep["totals"]
    out.append("blind suite %s: %d sets (%d single, %d clean, %d pairs); %d failed runs; %.0f s" % (
        rep.get("suite", ""), T["sets"], T["singles"], T["clean"], T["pairs"], T["runs_failed"],
        rep.get("wall_s", 0)))

    # confusion table
    conf = rep["confusion"]
    rows_l = ordered(list(conf)) + ([CLEAN] if CLEAN in conf else [])
    cols = set()
    for r in conf.values():
        cols.update(r)
    col_l = ordered(list(cols)) + [NOTHING]
    others = [c for c in col_l if c not in LABELS and c != NOTHING]
    ab = dict(ABBR)
    for i, c in enumerate(others):
        ab[c] = "?%d" % (i + 1)
    ab[NOTHING] = NOTHING
    out.append("\nConfusion (single-effect and clean sets): rows the true label, columns the first "
               "kept label")
    tab = []
    for r in rows_l:
        tab.append([r] + [conf[r].get(c, "") or "." for c in col_l] + [sum(conf[r].values())])
    out.append(fmt_table(tab, ["true \\ first kept"] + [ab[c] for c in col_l] + ["n"]) if tab
               else "(nothing scored)")
    legend = ["%s=%s" % (ab[c], c) for c in col_l if c != NOTHING]
    if legend:
        out.append("  " + "; ".join(legend))

    out.append("\nPer kind: named right first (first kept == truth)")
    tab = []
    for l, k in rep["per_kind"].items():
        tab.append([l, "%d/%d" % (k["named_right_first"], k["n"]), "%d/%d" % (k["named_anywhere"], k["n"]),
                    "%d/%d" % (k["best_right"], k["n"]),
                    "%d/%d" % (k.get("right_or_alike", 0), k["n"]),
                    "%d/%d" % (k["nothing"], k["n"]), k["failed"]])
    tot_r = sum(k["named_right_first"] for k in rep["per_kind"].values())
    tot_n = sum(k["n"] for k in rep["per_kind"].values())
    tot_a = sum(k.get("right_or_alike", 0) for k in rep["per_kind"].values())
    tab.append(["all single-effect sets", "%d/%d" % (tot_r, tot_n), "", "", "%d/%d" % (tot_a, tot_n),
                "", ""])
    out.append(fmt_table(tab, ["kind", "right first", "anywhere kept", "best right",
                               "best or alike", "nothing kept", "failed"]))

    c = rep["clean"]
    out.append("\nClean sets: nothing kept %d/%d%s" % (c["nothing_kept"], c["n"],
                                                       "  (%d failed)" % c["failed"] if c["failed"] else ""))
    cp = rep["counterparts"]
    out.append("Clean counterparts of the effect sets: nothing kept %d/%d" % (cp["nothing_kept"], cp["n"]))

    p = rep["pairs"]
    out.append("\nPairs: both effects kept %d/%d (at least one %d/%d)%s" % (
        p["both"], p["n"], p["at_least_one"], p["n"], "  (%d failed)" % p["failed"] if p["failed"] else ""))
    if p["rows"]:
        out.append(fmt_table([[r["id"], " + ".join(r["true"]), ", ".join(r["kept"]) or NOTHING,
                               "yes" if r["both"] else "no"] for r in p["rows"]],
                             ["set", "true", "kept (in order)", "both"]))

    out.append("\nAccuracy by strength tertile (single-effect sets, named right first)")
    out.append(fmt_table([["%d [%.2f, %.2f]" % (t["tertile"], *t["strength"]),
                           "%d/%d" % (t["named_right_first"], t["n"])] for t in rep["strength_tertiles"]],
                         ["tertile", "right"]))

    m = rep["mae_ratio"]
    out.append("\nMAE(final, effect set) / MAE(final, clean counterpart), single-effect sets named right")
    if m["rows"]:
        out.append(fmt_table([[r["id"], r["true"]] + ["%.2f" % r["ratio"][w] if r["ratio"][w] is not None
                                                      else "n/a" for w in WINDOWS] for r in m["rows"]],
                             ["set", "true"] + ["w=" + w for w in WINDOWS]))
    out.append("  <= %.2f: " % m["threshold"] + ", ".join(
        "w=%s %d/%d" % (w, v["le_%g" % m["threshold"]], v["n"]) for w, v in m["per_window"].items())
        + "; all windows %d/%d" % (m["all_windows_ok"], m["n"]))
    if m["named_right_without_counterpart"]:
        out.append("  (no ratio, counterpart failed: %s)" % ", ".join(m["named_right_without_counterpart"]))

    ti = rep.get("structure_took_in", {"extra": [], "other": []})
    if ti["extra"] or ti["other"]:
        out.append("\nModes of the trained model (the search's start), effect set against its clean "
                   "counterpart (not counted as named)")
        if ti["extra"]:
            out.append(fmt_table([[r["id"], " + ".join(r["true"]), r["counterpart_modes"], r["modes"],
                                   "yes" if r["more"] else "no", "yes" if r["named"] else "no"]
                                  for r in ti["extra"]],
                                 ["set", "true", "modes clean", "modes set", "took one in", "kept as term"]))
        out.append("  sets with an extra mode whose structure took more modes than the counterpart: "
                   "%d/%d; other effect sets (false alarms of that reading): %d/%d" % (
                       sum(r["more"] for r in ti["extra"]), len(ti["extra"]),
                       sum(r["more"] for r in ti["other"]), len(ti["other"])))

    jr = rep.get("junction_recheck")
    if jr and jr["runs"]:
        out.append("\nJunction re-checked after a kept term on %d of %d runs; the case log's "
                   "junction chosen on %d" % (jr["runs"], jr["scored_runs"], jr["case_log_chosen"]))

    sr = rep.get("structure_recheck")
    if sr and sr["runs"]:
        out.append("Structure re-checked after a kept term on the bias on %d of %d runs; chosen "
                   "again on %d" % (sr["runs"], sr["scored_runs"], sr["chosen_again"]))

    if rep.get("evidence"):
        out.extend(render_evidence(rep["evidence"]))

    out.append("\nFailures: %d" % len(rep["failures"]))
    for f in rep["failures"]:
        out.append("  %s (%s): %s" % (f["id"], f["run"], f["reason"]))
        if f["stderr_tail"].strip():
            out.extend("      | " + l for l in f["stderr_tail"].splitlines()[-8:])
    return "\n".join(out)


if __name__ == "__main__":
    sys.exit(main())
