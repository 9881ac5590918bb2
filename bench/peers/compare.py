"""The table of bench/peers/run.sh from its JSON lines: per-iteration CPU time of each peer and
tofcomp's lead over it, iterations to convergence, converged log-likelihood (and its distance
from the best of all), the converged fits' CPU time and tofcomp's lead. Every "tofcomp..." line
is one build of tofcomp (the default one is "tofcomp")."""
import json
import sys


def case_key(c):
    k, p = c.split("_")
    return int(k[1:]), int(p[1:])


def main(path):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    cases = sorted({r["case"] for r in rows}, key=case_key)
    builds = sorted({r["peer"] for r in rows if r["peer"].startswith("tofcomp")}, key=len)
    print()
    print("per EM iteration (CPU ms; tofcomp: plain EM, the same work per iteration as the peers):")
    header = f"{'case':>13} {'numpy':>8} {'flexmix':>8}"
    for b in builds:
        header += f" | {b:>26} {'numpy/it':>9} {'flexmix/it':>10}"
    print(header)
    for c in cases:
        by = {r["peer"]: r for r in rows if r["case"] == c}
        by.setdefault("flexmix", {"s_per_iteration": float("nan"), "iterations": 0,
                                  "log_likelihood": float("nan"), "fit_s": float("nan")})
        n, f = (by[p]["s_per_iteration"] * 1e3 for p in ("numpy", "flexmix"))
        line = f"{c:>13} {n:8.3f} {f:8.2f}"
        for b in builds:
            t = by[b]["s_per_iteration"] * 1e3
            line += f" | {t:26.3f} {n / t:9.1f} {f / t:10.1f}"
        print(line)
    print()
    print("converged fit: iterations (M-steps), E-steps, log-likelihood minus the best, CPU s, "
          "and that time over tofcomp's SQUAREM fit (the first build):")
    for c in cases:
        by = {r["peer"]: r for r in rows if r["case"] == c}
        by.setdefault("flexmix", {"iterations": 0, "log_likelihood": float("nan"),
                                  "fit_s": float("nan")})
        fits = []
        for b in builds:
            t = by[b]
            fits.append((f"{b} SQUAREM", t["squarem_iterations"], t["squarem_e_steps"],
                         t["squarem_log_likelihood"], t["squarem_fit_s"]))
        for b in builds:
            t = by[b]
            fits.append((f"{b} plain EM", t["iterations"], t["iterations"] + 1,
                         t["log_likelihood"], t["fit_s"]))
        fits.append(("numpy plain EM", by["numpy"]["iterations"], by["numpy"]["iterations"] + 1,
                     by["numpy"]["log_likelihood"], by["numpy"]["fit_s"]))
        fits.append(("flexmix", by["flexmix"]["iterations"], by["flexmix"]["iterations"],
                     by["flexmix"]["log_likelihood"], by["flexmix"]["fit_s"]))
        best = max(f[3] for f in fits if f[3] == f[3])
        reference = fits[0][4]
        print(f"  {c}")
        for name, iters, e_steps, loglik, seconds in fits:
            print(f"    {name:>36} {iters:7d} it {e_steps:7d} E {loglik - best:12.6f} "
                  f"{seconds:9.3f} s {seconds / reference:8.1f}x")


if __name__ == "__main__":
    main(sys.argv[1])
