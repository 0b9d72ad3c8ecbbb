#!/usr/bin/env bash
# report.sh - run the benchmarks and write their tables into the docs.
#
#   bench/report.sh [BUILD_DIR] [RUNS]
#     BUILD_DIR  a Release build with softlight, softlight-gl, bench_raster, bench_shading and
#                bench_texture (default build)
#     RUNS       runs of each benchmark; every figure written is the median over the runs of
#                each run's own median over frames (default 3)
#
# Rewrites, in place, the text between marker lines
#     <!-- bench:begin NAME -->
#     <!-- bench:end -->
# in docs/performance.md (stamp, raster, lighting, texture, vs-gl, viewer) and README.md
# (readme), and leaves every other line alone. The stamp block, and the end of the README's
# block, is a dated line: when, on which CPU, how many cores, the load average before and
# after, which commit. The README block also carries
# accuracy figures, read from docs/accuracy/speed-vs-error.csv (written by
# bench/speed-vs-error.sh, which is not rerun here: it takes from minutes to an hour).
#
# What runs, with OMP_WAIT_POLICY=passive (spinning OpenMP threads distort timings on a shared
# machine):
#   bench_raster --threads 1,2 --tiles 64 --frames 5           RUNS times
#   bench_shading --n 20,40,80 --threads 1,2 --frames 3        RUNS times (batched path)
#   bench_shading --n 40 --threads 1,2 --frames 1 --plain      RUNS times (the line-by-line port)
#   bench_texture --rounds RUNS                                each texture format, one thread
#   bench/vs-gl.sh BUILD_DIR RUNS 3                            every shipped scene
#   softlight view SCENE --size 1280x720 --benchmark 40 --move-div 1 under xvfb-run, RUNS times a
#                                                              scene (skipped without xvfb-run)
# About 4 minutes on an idle 2-core machine with RUNS = 3.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/cpu_frame.bash # vector_isa
BUILD=${1:-build}
RUNS=${2:-3}
export OMP_WAIT_POLICY=passive
for p in softlight softlight-gl bench_raster bench_shading bench_texture; do
    [ -x "$BUILD/$p" ] || { echo "report.sh: $BUILD/$p not built" >&2; exit 2; }
done
T=$(mktemp -d "${TMPDIR:-/tmp}/report.XXXXXX")
trap 'rm -rf "$T"' EXIT
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "nan"; else print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
load() { cut -d' ' -f1-3 /proc/loadavg; }

load_before=$(load)
start=$(date -u '+%Y-%m-%d %H:%M UTC')

# --- rasterizer: "threads tris_ms Mtri fill_ms Mfrag" per run and thread count
echo "report.sh: bench_raster x $RUNS" >&2
for ((r = 0; r < RUNS; r++)); do
    "$BUILD/bench_raster" --threads 1,2 --tiles 64 --frames 5 |
        awk -F'|' '/^ *64 +[12] \|/ { split($1, a, " "); split($2, b, " "); split($3, c, " "); print a[2], b[1], b[2], c[1], c[2] }'
done >"$T/raster"
{
    echo '| threads | sphere: ms a frame | million triangles/s | fill: ms a frame | million fragments/s |'
    echo '|---:|---:|---:|---:|---:|'
    for t in 1 2; do
        col() { awk -v t=$t -v c="$1" '$1 == t { print $c }' "$T/raster" | median; }
        printf '| %d | %.1f | %.2f | %.1f | %.0f |\n' $t "$(col 2)" "$(col 3)" "$(col 4)" "$(col 5)"
    done
    t1=$(awk '$1 == 1 { print $2 }' "$T/raster" | median) t2=$(awk '$1 == 2 { print $2 }' "$T/raster" | median)
    f1=$(awk '$1 == 1 { print $4 }' "$T/raster" | median) f2=$(awk '$1 == 2 { print $4 }' "$T/raster" | median)
    echo
    awk -v a="$t1" -v b="$t2" -v c="$f1" -v d="$f2" \
        'BEGIN { printf "Second thread: sphere %.2fx, fill %.2fx.\n", a / b, c / d }'
} >"$T/raster.md"

# --- lighting pass alone: "N threads ms ns" per run
echo "report.sh: bench_shading x $RUNS" >&2
for ((r = 0; r < RUNS; r++)); do
    "$BUILD/bench_shading" --frames 3 --n 20,40,80 --threads 1,2 | awk '$2 ~ /%$/ { print "batched", $1, $3, $4, $5 }'
    "$BUILD/bench_shading" --frames 1 --n 40 --threads 1,2 --plain | awk '$2 ~ /%$/ { print "plain", $1, $3, $4, $5 }'
done >"$T/shading"
{
    echo '| path | N | 1 thread, ms | 2 threads, ms | second thread | ns a sample (1 thread) |'
    echo '|---|---:|---:|---:|---:|---:|'
    for key in "batched 20" "batched 40" "batched 80" "plain 40"; do
        set -- $key
        m1=$(awk -v p=$1 -v n=$2 '$1 == p && $2 == n && $3 == 1 { print $4 }' "$T/shading" | median)
        m2=$(awk -v p=$1 -v n=$2 '$1 == p && $2 == n && $3 == 2 { print $4 }' "$T/shading" | median)
        ns=$(awk -v p=$1 -v n=$2 '$1 == p && $2 == n && $3 == 1 { print $5 }' "$T/shading" | median)
        awk -v p=$1 -v n=$2 -v a="$m1" -v b="$m2" -v s="$ns" \
            'BEGIN { printf "| %s | %d | %.1f | %.1f | %.2fx | %.1f |\n", p, n, a, b, a / b, s }'
    done
} >"$T/lighting.md"

# --- texture sampling, one thread, each format
echo "report.sh: bench_texture" >&2
"$BUILD/bench_texture" --rounds "$RUNS" >"$T/texture.txt"
{
    echo '| format | bytes a texel | trilinear, ns | bilinear, ns | nearest, ns |'
    echo '|---|---:|---:|---:|---:|'
    awk 'NF == 6 && $2 ~ /^[0-9]+$/ { printf "| %s | %s | %s | %s | %s |\n", $1, $2, $4, $5, $6 }' "$T/texture.txt"
} >"$T/texture.md"

# --- against Mesa's llvmpipe, every shipped scene
echo "report.sh: vs-gl.sh, $RUNS rounds" >&2
bash bench/vs-gl.sh "$BUILD" "$RUNS" 3 >"$T/vsgl.txt"
renderer=$(head -1 "$T/vsgl.txt" | sed -E 's/^softlight vs softlight-gl \((.*)\), [0-9]+ rounds.*/\1/')
{
    echo '| scene | C G-buffer, ms | GL G-buffer, ms | ratio | C lighting, ms | GL lighting, ms | ratio | C frame, ms | GL frame, ms | ratio |'
    echo '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|'
    awk -F'|' 'NR > 2 { gsub(/ +$/, "", $1); split($2, a, " "); split($3, b, " "); split($4, c, " ");
        printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, a[1], a[2], a[3], b[1], b[2], b[3], c[1], c[2], c[3] }' "$T/vsgl.txt"
} >"$T/vsgl.md"

# --- the viewer while the camera moves, 1280x720
: >"$T/viewer.md"
if command -v xvfb-run >/dev/null; then
    echo "report.sh: viewer x $RUNS per scene" >&2
    {
        echo '| scene | frame, ms | frames a second | raster, ms | lighting and tone map, ms | present, ms |'
        echo '|---|---:|---:|---:|---:|---:|'
        for scene in scenes/*.json; do
            for ((r = 0; r < RUNS; r++)); do
                xvfb-run -a -s "-screen 0 1920x1080x24" "$BUILD/softlight" view "$scene" --size 1280x720 \
                    --benchmark 40 --move-div 1 2>/dev/null | grep 'benchmark:' |
                    sed -E 's/.*frame median ([0-9.]+) ms.*raster ([0-9.]+), lighting ([0-9.]+), tone map ([0-9.]+), present ([0-9.]+) ms.*/\1 \2 \3 \4 \5/'
            done >"$T/view"
            col() { awk -v c="$1" '{ print $c }' "$T/view" | median; }
            f=$(col 1)
            awk -v s="$(basename "$scene" .json)" -v f="$f" -v r="$(col 2)" -v l="$(col 3)" -v t="$(col 4)" -v p="$(col 5)" \
                'BEGIN { printf "| %s | %.1f | %.0f | %.1f | %.1f | %.1f |\n", s, f, 1000 / f, r, l + t, p }'
        done
    } >"$T/viewer.md"
fi

load_after=$(load)
cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
isa=$(vector_isa)
# the commit the programs were built from: the source tree of the build's CMake cache
src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$BUILD/CMakeCache.txt" 2>/dev/null)
commit=$(git -C "${src:-.}" rev-parse --short HEAD 2>/dev/null || echo unknown)
stamp="Measured $start by \`bench/report.sh\` ($RUNS runs, medians) with a Release build of commit \
$commit: $cpu ($isa), $(nproc) cores, load average $load_before before and $load_after after (other \
work on the machine counts in it)."
echo "$stamp" >"$T/stamp.md"

# --- the README's summary: a few figures from the tables above and from the accuracy sweep's CSV
python3 - "$T" "$renderer" >"$T/readme.md" <<'EOF'
import csv, os, sys
t, renderer = sys.argv[1], sys.argv[2]
def rows(name):
    return [l.split() for l in open(os.path.join(t, name)) if l.strip()]
def med(v):
    v = sorted(v); n = len(v)
    return v[n // 2] if n % 2 else (v[n // 2 - 1] + v[n // 2]) / 2
r = rows('raster')
tri2 = med([float(x[2]) for x in r if x[0] == '2']); frag2 = med([float(x[4]) for x in r if x[0] == '2'])
s = rows('shading')
def light(path, n, th):
    return med([float(x[3]) for x in s if x[0] == path and x[1] == str(n) and x[2] == str(th)])
ratios = []
for l in open(os.path.join(t, 'vsgl.txt')).read().splitlines()[2:]:
    p = l.split('|')
    ratios.append((float(p[2].split()[2]), float(p[3].split()[2])))
print('| what | figure | command |')
print('|---|---|---|')
print(f'| rasterizer, 1920x1080, 2 threads | {tri2:.1f} million triangles/s, {frag2:.0f} million depth-tested fragments/s | `bench_raster --threads 1,2 --tiles 64` |')
print(f'| lighting pass, 1280x720, N = 40, 2 threads | {light("batched", 40, 2):.0f} ms (the line-by-line port: {light("plain", 40, 2):.0f} ms) | `bench_shading --n 40` |')
lo = min(x[0] for x in ratios); hi = max(x[0] for x in ratios)
flo = min(x[1] for x in ratios); fhi = max(x[1] for x in ratios)
print(f'| time against {renderer} running the same GLSL, every shipped scene | lighting {lo:.2f}-{hi:.2f}, whole frame {flo:.2f}-{fhi:.2f} of llvmpipe\'s time | `bench/vs-gl.sh` |')
try:
    c = {(x['scene'], x['variant']): x for x in csv.DictReader(open('docs/accuracy/speed-vs-error.csv')) if x['renderer'] == 'softlight'}
    spec = c[('all', 'spec spec-d4 N40')]; best = c[('all', 'mf pdf+dist+env64 N16')]
    split = c[('all', 'splitsum spec-d4 N40')]
    when = os.popen('git log -1 --format=%cs -- docs/accuracy/speed-vs-error.csv').read().strip() or 'unknown'
    print(f'| nRMSE against the brute-force ground truth, five Phong scenes (sweep of {when}) | '
          f'the specification\'s recipe at N = 40: {float(spec["total_nrmse"]):.3f}; '
          f'`--estimator mf --lod pdf --distortion --env-lights 64 -n 16`: {float(best["total_nrmse"]):.4f}; '
          f'`--estimator splitsum`: {float(split["total_nrmse"]):.3f} | `bench/speed-vs-error.sh` |')
except (OSError, KeyError) as e:
    print(f'| accuracy | not available ({e}) | `bench/speed-vs-error.sh` |')
EOF

# --- write the blocks between their markers
python3 - "$T" <<'EOF'
import os, re, sys
t = sys.argv[1]
stamp = open(os.path.join(t, 'stamp.md')).read().strip()
blocks = {'raster': 'raster.md', 'lighting': 'lighting.md', 'texture': 'texture.md', 'vs-gl': 'vsgl.md', 'viewer': 'viewer.md',
          'readme': 'readme.md', 'stamp': None}
for doc in ('docs/performance.md', 'README.md'):
    text = open(doc, encoding='utf-8').read()
    def fill(m):
        name = m.group(1)
        if name not in blocks:
            return m.group(0)
        body = stamp if blocks[name] is None else open(os.path.join(t, blocks[name])).read().strip()
        if not body:
            body = '(not measured: xvfb-run was not found)'
        if name == 'readme':
            body += '\n\n*' + stamp + '*'
        return f'<!-- bench:begin {name} -->\n{body}\n<!-- bench:end -->'
    new = re.sub(r'<!-- bench:begin ([a-z-]+) -->\n.*?<!-- bench:end -->', fill, text, flags=re.S)
    with open(doc, 'w', encoding='utf-8') as f:
        f.write(new)
    print(f'report.sh: {doc} updated', file=sys.stderr)
EOF
