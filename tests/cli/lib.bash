# lib.bash - what the command-line tests share. A test sources it after `set -u`:
#   . "$(dirname "$0")/lib.bash"; cli_init NAME "$@"
# cli_init sets SL (the build's softlight program, from BUILD_DIR, the test's first argument),
# T (a temporary directory, removed on exit) and the counters `passes` and `fails` that ok, bad
# and cli_done keep. CTest runs the tests from the source root.

# cli_init NAME BUILD_DIR
cli_init() {
    SL=${2:?usage: $0 BUILD_DIR}/softlight
    T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-$1.XXXXXX")
    trap 'rm -rf "$T"' EXIT
    fails=0 passes=0
}

ok() { echo "ok   $*"; passes=$((passes + 1)); }
bad() { echo "FAIL $*"; fails=$((fails + 1)); }

# one_error PATTERN COMMAND...: runs COMMAND, its stdout into $T/out and its stderr into $T/err;
# true when it exits with status 2 and one stderr line that matches PATTERN (grep -E). Leaves
# the status and the count of stderr lines in err_status and err_lines.
one_error() {
    local pattern=$1; shift
    "$@" >"$T/out" 2>"$T/err"
    err_status=$?
    err_lines=$(wc -l <"$T/err")
    [ "$err_status" -eq 2 ] && [ "$err_lines" -eq 1 ] && grep -qE -- "$pattern" "$T/err"
}

# expect_error NAME PATTERN -- COMMAND...: COMMAND fails with status 2 and one stderr line
# matching PATTERN; ok prints that line, bad what came instead.
expect_error() {
    local name=$1 pattern=$2; shift 3
    if one_error "$pattern" "$@"; then
        ok "$name: $(cat "$T/err")"
    else
        bad "$name: status $err_status, $err_lines stderr lines (want 2, 1 matching /$pattern/):"
        sed 's/^/    /' "$T/err" | head -5
    fi
}

# consumer_toolchain BUILD_DIR: sets CC and CFLAGS for a program built against that build's
# installed library as the library was built: its compiler (GCC's and clang's OpenMP runtimes
# differ) and, in a sanitized build, the sanitizers' runtime.
consumer_toolchain() {
    CC=$(sed -n 's/^CMAKE_C_COMPILER:[A-Z]*=//p' "$1/CMakeCache.txt")
    CFLAGS=""
    if grep -q '^SL_SANITIZE:BOOL=ON' "$1/CMakeCache.txt"; then
        CFLAGS="-fsanitize=address,undefined"
    fi
}

# cli_done [LABEL]: the counts, and the test's status.
cli_done() {
    echo "${1:+$1: }$passes passed, $fails failed"
    [ "$fails" -eq 0 ]
}
