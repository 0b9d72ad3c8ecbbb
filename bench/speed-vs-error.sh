#!/usr/bin/env bash
# speed-vs-error.sh - the speed-against-error sweep in one go (issue 7): runs bench_speed_vs_error
# (ground truth cached in out/ground-truth, CSV and plot data in out/speed-vs-error, the report in
# docs/accuracy.md), then gnuplot for the report's plots in docs/accuracy/.
#
#   bench/speed-vs-error.sh [BUILD_DIR] [-- extra bench_speed_vs_error options]
#
# Run from anywhere; works in the source root. BUILD_DIR defaults to build (a Release build with
# bench_speed_vs_error and, for the GL rows, softlight-gl). First run: about 15 minutes on a
# 2-core machine, most of it the ground truth; later runs reuse the cache (a few minutes).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
bench="$build/bench_speed_vs_error"
if [ ! -x "$bench" ]; then
    echo "speed-vs-error: $bench not found; build first: cmake --build $build --target bench_speed_vs_error" >&2
    exit 2
fi
data=out/speed-vs-error
# passive OpenMP waiting: spinning threads on a shared machine distort every timing (docs/performance.md)
OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive} "$bench" --out "$data" --cache out/ground-truth \
    --doc docs/accuracy.md "$@"
mkdir -p docs/accuracy
plot() { # col, ylabel, output
    gnuplot -e "dir='$data'; out='docs/accuracy/$3'; col=$1; ylab='$2'" bench/gnuplot/speed-vs-error.gp
}
if command -v gnuplot >/dev/null; then
    plot 3 'nRMSE, total' speed-vs-error.png
    plot 4 'nRMSE, specular' specular-vs-time.png
    plot 6 'share of pixels > 8/255 off' over8-vs-time.png
    cp "$data/speed-vs-error.csv" docs/accuracy/speed-vs-error.csv
    echo "plots in docs/accuracy/, CSV in $data/speed-vs-error.csv (copy in docs/accuracy/)"
else
    echo "speed-vs-error: gnuplot not found: no plots (the CSV and docs/accuracy.md are written)" >&2
fi
