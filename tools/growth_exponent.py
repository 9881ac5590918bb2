#!/usr/bin/env python3
"""Fits the growth exponent b of time ≈ a·K^b from Google Benchmark JSON output.

Usage: build/bench/em_bench --benchmark_format=json > em.json
       python3 tools/growth_exponent.py em.json
Groups the runs by benchmark name and every argument but the first (K), and fits log(time)
against log(K) by least squares for each group with at least three sizes.
"""
import json
import math
import sys
from collections import defaultdict


def fit(points):
    xs = [math.log(k) for k, _ in points]
    ys = [math.log(t) for _, t in points]
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    return sxy / sxx


def main(path):
    with open(path, encoding="utf-8") as f:
        runs = json.load(f)["benchmarks"]
    groups = defaultdict(list)
    for run in runs:
        if run.get("run_type", "iteration") != "iteration":
            continue
        parts = run["name"].split("/")
        name = parts[0]
        args = [p for p in parts[1:] if not p.startswith("min_time")]
        key = (name, tuple(args[1:]))
        groups[key].append((float(args[0]), float(run["real_time"])))
    print(f"{'benchmark':<24} {'other args':<12} {'sizes':>5} {'exponent':>9}")
    for (name, rest), points in sorted(groups.items()):
        if len(points) >= 3:
            print(f"{name:<24} {'/'.join(rest) or '-':<12} {len(points):>5} {fit(points):>9.3f}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
