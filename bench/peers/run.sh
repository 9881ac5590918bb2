#!/usr/bin/env bash
# The exact EM of §5 side by side: tofcomp's engine, numpy and R's flexmix on the same data in one
# run (docs/performance.md, "Peers"). Writes the cases (bench/peers/make_data.py) into a
# temporary folder, runs each peer on each, and prints per-iteration CPU times, iterations to
# convergence, converged log-likelihoods and the ratios (bench/peers/compare.py).
#
# Usage: bench/peers/run.sh [BUILD_DIR] [SIZES] [COLUMNS]
#   BUILD_DIR defaults to build/ (needs bench/peer_engine); SIZES 10000,100000; COLUMNS 3,17.
#   TOFCOMP_PEER_EXTRA_BUILD: a second build of tofcomp (e.g. one configured with
#   -DTOFCOMP_ARCH=x86-64-v3) run beside the first, labelled by its TOFCOMP_ARCH.
# Needs bench/peers/setup.sh (numpy, threadpoolctl, OpenBLAS, R's flexmix).
#
# Every peer runs single-threaded (OPENBLAS_NUM_THREADS=1) and is timed in CPU time of its own
# process, so other load on a shared machine does not count. numpy and R load OpenBLAS
# (Debian's libopenblas0-pthread) through LD_LIBRARY_PATH, whatever the system's BLAS
# alternative; OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE, which this workplace may set for old
# OpenBLAS builds and which slow a current one, are unset for these commands alone, and the
# kernel OpenBLAS then runs is printed (threadpoolctl).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
sizes=${2:-10000,100000}
columns=${3:-3,17}
iterations=${TOFCOMP_PEER_ITERATIONS:-20}
repeats=${TOFCOMP_PEER_REPEATS:-3}
flexmix_tolerance=${TOFCOMP_FLEXMIX_TOLERANCE:-1e-10}
openblas=/usr/lib/x86_64-linux-gnu/openblas-pthread
python=${TOFCOMP_PEER_PYTHON:-/usr/bin/python3}  # Debian's, with its numpy
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
peer_env=(env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE OPENBLAS_NUM_THREADS=1
          OMP_NUM_THREADS=1 LD_LIBRARY_PATH="$openblas")

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
"${peer_env[@]}" "$python" -c '
import numpy, threadpoolctl
for lib in threadpoolctl.threadpool_info():
    print("numpy", numpy.__version__, "BLAS:", lib["internal_api"], lib["version"],
          "kernel", lib["architecture"], "threads", lib["num_threads"])'
echo "R: $(Rscript -e 'cat(R.version.string, "flexmix", as.character(packageVersion("flexmix")))')"
"$python" "$here/make_data.py" "$work" "$sizes" "$columns" >/dev/null
results="$work/results.jsonl"
for k in ${sizes//,/ }; do
  for p in ${columns//,/ }; do
    case="k${k}_p${p}"
    "$build/bench/peer_engine" "$work" "$case" "$iterations" "$repeats" tofcomp | tee -a "$results"
    if [ -n "${TOFCOMP_PEER_EXTRA_BUILD:-}" ]; then
      arch=$(sed -n 's/^TOFCOMP_ARCH:STRING=//p' "$TOFCOMP_PEER_EXTRA_BUILD/CMakeCache.txt")
      "$TOFCOMP_PEER_EXTRA_BUILD/bench/peer_engine" "$work" "$case" "$iterations" "$repeats" \
        "tofcomp -march=${arch:-default}" | tee -a "$results"
    fi
    "${peer_env[@]}" "$python" "$here/em_numpy.py" "$work" "$case" "$iterations" "$repeats" | tee -a "$results"
    # A peer that fails is reported and left out of the table, the run goes on.
    if ! "${peer_env[@]}" Rscript "$here/em_flexmix.R" "$work" "$case" "$iterations" \
        "$flexmix_tolerance" 100000 >"$work/flexmix.out" 2>"$work/flexmix.err"; then
      echo "flexmix failed on $case:" >&2
      cat "$work/flexmix.err" >&2
    fi
    tee -a "$results" <"$work/flexmix.out"
  done
done
"$python" "$here/compare.py" "$results"
