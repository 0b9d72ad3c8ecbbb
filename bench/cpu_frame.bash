# cpu_frame.bash - what the frame-cost benchmarks share (sourced from the repository's root:
# bench/shadows.sh, bench/reflection-occlusion.sh; bench/report.sh, bench/mis-front.sh and
# bench/visibility-cost.sh take vector_isa).
#
# frame_bench_args NAME [BUILD_DIR] [ROUNDS] [SIZE]: the benchmarks' arguments into BUILD, ROUNDS
# and SIZE (defaults build, 3, 1280x720), and T, a temporary directory removed on exit.
frame_bench_args() {
    local name=$1
    BUILD=${2:-build}
    ROUNDS=${3:-3}
    SIZE=${4:-1280x720}
    T=$(mktemp -d "${TMPDIR:-/tmp}/$name.XXXXXX")
    trap 'rm -rf "$T"' EXIT
}
#
# vector_isa: the widest vectors this CPU has, AVX-512, AVX2 or SSE. A -march=native build runs
# its vector loops at that width, so each benchmark's stamp names it: figures compare only
# between machines of the same kind.
vector_isa() {
    local flags
    flags=$(grep -m1 '^flags' /proc/cpuinfo)
    case " $flags " in
    *" avx512f "*) echo AVX-512 ;;
    *" avx2 "*) echo AVX2 ;;
    *) echo SSE ;;
    esac
}
#
# median: the median of the numbers on stdin, one a line.
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# cpu SCENE REPEAT OPTIONS...: user + system seconds of one render of scenes/SCENE.json (SCENE
# itself when it names a .json file) at SIZE on one thread (-j 1: no OpenMP spinning counted)
# with --repeat REPEAT; what render prints goes to $T/out.txt. CPU time, which a loaded machine
# inflates far less than wall time.
cpu() {
    local s=$1 n=$2 file
    shift 2
    case $s in *.json) file=$s ;; *) file=scenes/$s.json ;; esac
    /usr/bin/time -f "%U %S" -o "$T/time" "$BUILD/softlight" render "$file" --size "$SIZE" -j 1 "$@" \
        --repeat "$n" -o "$T/f.png" >"$T/out.txt"
    awk '{ print $1 + $2 }' "$T/time"
}
# frame_cpu SCENE OPTIONS...: the CPU seconds of one frame, (--repeat 4 less --repeat 1) / 3, so
# that the setup and the one-off work (maps drawn once per scene) cancel.
frame_cpu() {
    local s=$1 a b
    shift
    a=$(cpu "$s" 4 "$@")
    b=$(cpu "$s" 1 "$@")
    awk -v a="$a" -v b="$b" 'BEGIN { printf "%.4f", (a - b) / 3 }'
}
