# view_common.bash - shared by the tests/cli/view_*.sh scripts (sourced, not run: CTest runs *.sh).
#
# view_setup BUILD_DIR: finds softlight, fails LOUDLY when Xvfb (xvfb-run) is missing - the
# viewer test must not pass by skipping (scripts/setup.sh installs xvfb) - and makes a temporary
# directory $T, removed on exit (kept when VIEW_TEST_KEEP is set).
# view_run ARGS...: `softlight view ARGS` on a fresh Xvfb server, with a time limit; sets $rc.
# view_same A.hdr B.hdr LABEL / view_differ A.hdr B.hdr LABEL: softlight compare checks.

VIEW_TEST_SIZE=320x180
VIEW_TEST_LIMIT=${VIEW_TEST_LIMIT:-90} # seconds for one viewer run (an ASan build is slower)

fail() {
    echo "FAIL: $*"
    exit 1
}

view_setup() {
    BUILD=${1:?usage: $0 BUILD_DIR}
    SL=$BUILD/softlight
    [ -x "$SL" ] || fail "$SL was not built"
    command -v xvfb-run >/dev/null || fail "xvfb-run is not installed (Debian package xvfb; run scripts/setup.sh)"
    command -v Xvfb >/dev/null || fail "Xvfb is not installed (Debian package xvfb; run scripts/setup.sh)"
    command -v xauth >/dev/null || fail "xauth is not installed (xvfb-run needs it; run scripts/setup.sh)"
    if "$SL" view --help 2>&1 | grep -q "built without SDL2"; then
        fail "softlight was built without SDL2 (install libsdl2-dev libsdl2-ttf-dev)"
    fi
    T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-view-test.XXXXXX")
    if [ -n "${VIEW_TEST_KEEP:-}" ]; then
        echo "keeping $T"
    else
        trap 'rm -rf "$T"' EXIT
    fi
    # X and Mesa keep allocations until exit; leak reports from them are not the viewer's.
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
}

# view_run ARGS...: output in $T/out.txt and $T/err.txt, exit status in $rc, seconds in $secs.
view_run() {
    local start end
    start=$(date +%s.%N)
    set +e
    xvfb-run -a -s "-screen 0 1024x768x24 -nolisten tcp" \
        timeout "$VIEW_TEST_LIMIT" "$SL" view "$@" >"$T/out.txt" 2>"$T/err.txt"
    rc=$?
    set -e
    end=$(date +%s.%N)
    secs=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
    echo "softlight view $* -> exit $rc in ${secs}s"
    sed 's/^/  out: /' "$T/out.txt"
    sed 's/^/  err: /' "$T/err.txt"
}

view_expect_exit0() {
    [ "$rc" -eq 124 ] && fail "$1: the viewer did not finish within ${VIEW_TEST_LIMIT}s"
    [ "$rc" -eq 0 ] || fail "$1: exit status $rc, expected 0"
}

# view_same A B LABEL [TOL]: largest absolute difference at most TOL (default 1e-6; both sides
# are the same pipeline, so anything above rounding is a real difference).
view_same() {
    local tol=${4:-1e-6}
    [ -s "$1" ] || fail "$3: $1 was not written"
    if ! "$SL" compare "$1" "$2" --metric max --tolerance "$tol" >"$T/cmp.txt" 2>&1; then
        cat "$T/cmp.txt"
        fail "$3: $1 and $2 differ by more than $tol"
    fi
    echo "ok: $3 ($(grep -E '^PASS' "$T/cmp.txt"))"
}

# view_differ A B LABEL: RMSE above 1e-3, i.e. the image visibly changed.
view_differ() {
    [ -s "$1" ] || fail "$3: $1 was not written"
    local status=0
    "$SL" compare "$1" "$2" --tolerance 1e-3 >"$T/cmp.txt" 2>&1 || status=$?
    if [ "$status" -ne 1 ]; then
        cat "$T/cmp.txt"
        fail "$3: expected $1 to differ from $2 (compare exit $status)"
    fi
    echo "ok: $3 ($(grep -E '^FAIL' "$T/cmp.txt" | sed 's/FAIL //'))"
}
