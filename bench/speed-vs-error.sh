#!/usr/bin/env bash
# speed-vs-error.sh - the speed-against-error sweep in one go: runs bench_speed_vs_error
# (ground truth cached in out/ground-truth, CSV and plot data in out/speed-vs-error, the report in
# docs/accuracy.md), then gnuplot for the report's plots in docs/accuracy/.
#
#   bench/speed-vs-error.sh [BUILD_DIR] [--shards N] [-- extra bench_speed_vs_error options]
#
# After the report, bench/sweep_fronts.py appends its split-sum and GGX Pareto tables (from the CSV),
# then docs/accuracy/mis.md, the MIS section (its figures: bench/mis-front.sh), docs/accuracy/uses.md
# (which mode for which use), and the visibility
# section of bench/visibility-error.sh's last run (docs/accuracy/visibility.md).
#
# --shards N: the ground truth first, as N `softlight truth --shard I/N` runs per scene under GNU
# parallel (add -S hosts to the parallel line to spread them over machines; docs/sharding.md),
# merged into out/ground-truth/sharded/NAME-WxH/, which the sweep then reads (--truth) and checks.
# Each shard keeps its own cache there, so a rerun with unchanged inputs integrates nothing.
#
# Run from anywhere; works in the source root. BUILD_DIR defaults to build (a Release build with
# bench_speed_vs_error and, for the GL rows, softlight-gl). First run: about 15 minutes on a
# 2-core machine, most of it the ground truth; later runs reuse the cache (a few minutes).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ $# -gt 0 ] && shift
shards=0
if [ "${1:-}" = "--shards" ]; then
    shards=${2:?--shards needs a count}
    shift 2
fi
[ "${1:-}" = "--" ] && shift
bench="$build/bench_speed_vs_error"
if [ ! -x "$bench" ]; then
    echo "speed-vs-error: $bench not found; build first: cmake --build $build --target bench_speed_vs_error" >&2
    exit 2
fi
if [ "$shards" -gt 0 ]; then
    command -v parallel >/dev/null || { echo "speed-vs-error: --shards needs GNU parallel (apt-get install parallel)" >&2; exit 2; }
    truth=out/ground-truth/sharded
    mkdir -p "$truth/cache"
    "$bench" --truth-jobs "$@" | while read -r name scene w h; do
        dir=$truth/$name-${w}x$h
        echo "speed-vs-error: ground truth of $name at ${w}x$h in $shards shards" >&2
        parallel --halt now,fail=1 "$build/softlight" truth "$scene" --size "${w}x$h" --parts "$dir" --threads 1 \
            --cache "$truth/cache/$name-${w}x$h-{}-of-$shards.gt" --shard "{}/$shards" ::: $(seq "$shards") >/dev/null
        "$build/softlight" merge "$dir".shard-*-of-"$shards" >/dev/null
        rm -f "$dir".shard-*-of-"$shards"
    done
    set -- --truth "$truth" "$@"
fi
data=out/speed-vs-error
# passive OpenMP waiting: spinning threads on a shared machine distort every timing (docs/performance.md)
OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive} "$bench" --out "$data" --cache out/ground-truth \
    --doc docs/accuracy.md "$@"
# the report's last sections, from the same run's CSV: the Pareto fronts of the Phong and GGX sets
# with split-sum's place on each, split-sum per scene (bench/sweep_fronts.py); appended to the
# report wherever --doc sent it
doc=docs/accuracy.md prev=
for a in "$@"; do [ "$prev" = --doc ] && doc=$a; prev=$a; done
python3 bench/sweep_fronts.py "$data/speed-vs-error.csv" --dat "$data" >"$data/fronts.md"
[ "$doc" = none ] || cat "$data/fronts.md" >>"$doc"
# the MIS estimator's own front on environments generated outside the repository
# (docs/accuracy/mis.md, the section, and docs/accuracy/mis-front.md, bench/mis-front.sh's table)
[ "$doc" = none ] || cat docs/accuracy/mis.md docs/accuracy/mis-front.md >>"$doc"
# which mode for which use (docs/accuracy/uses.md: its figures are the tables')
[ "$doc" = none ] || cat docs/accuracy/uses.md >>"$doc"
# the visibility section (bench/visibility-error.sh, its own run), kept across this report's rewrites
[ "$doc" = none ] || [ ! -f docs/accuracy/visibility.md ] || { echo; cat docs/accuracy/visibility.md; } >>"$doc"
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
