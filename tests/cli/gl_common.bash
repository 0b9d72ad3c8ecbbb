# gl_common.bash - shared by the tests/cli/gl_*.sh scripts (sourced, not run: CTest runs *.sh).
#
# gl_setup BUILD_DIR: finds softlight and softlight-gl, skips the test (exit 0 with a SKIP line)
# when and only when softlight-gl cannot get an OpenGL context here, and makes a temporary
# directory $T removed on exit (kept, for a look at the images, when GL_TEST_KEEP is set). Renders are small (GL_TEST_SIZE) so the suite stays fast on llvmpipe.

GL_TEST_SIZE=${GL_TEST_SIZE:-320x180}

gl_setup() {
    BUILD=${1:?usage: $0 BUILD_DIR}
    SL=$BUILD/softlight
    GL=$BUILD/softlight-gl
    if [ ! -x "$GL" ]; then
        echo "FAIL: $GL was not built (CMake found no EGL or libepoxy)"
        exit 1
    fi
    local why
    if ! why=$("$GL" info 2>&1 >/dev/null); then
        echo "SKIP: softlight-gl cannot create an OpenGL context here: $why"
        exit 0
    fi
    "$GL" info | head -1
    if ! "$SL" render --help >/dev/null 2>&1; then
        echo "FAIL: '$SL render' is not available"
        exit 1
    fi
    T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-gl-test.XXXXXX")
    if [ -n "${GL_TEST_KEEP:-}" ]; then
        echo "keeping $T"
    else
        trap 'rm -rf "$T"' EXIT
    fi
}

# gl_field NAME FILE: the first number on the line of `softlight compare` output starting with NAME.
gl_field() {
    awk -v key="$1" 'index($0, key) == 1 { sub(key, ""); print $1 + 0; exit }' "$2"
}

# gl_check_share LABEL FILE MAX_PERCENT: the "8-bit diff > 8" share must not exceed MAX_PERCENT.
gl_check_share() {
    local share
    share=$(awk '/^8-bit diff > 8/ { sub("%", "", $5); print $5; exit }' "$2")
    if awk -v s="$share" -v m="$3" 'BEGIN { exit !(s <= m) }'; then
        return 0
    fi
    echo "FAIL $1: ${share}% of pixels differ by more than 8/255 after the tone map (allowed $3%)"
    return 1
}

# gl_within NAME A B: the gl_shading.sh bounds between images A and B (p99 relative error at most
# 0.05, at most 0.1% of pixels more than 8/255 apart after the tone map), the figures printed; the
# comparison's output in $T/NAME.txt. The shadow and sky-map tests run it per case.
gl_within() {
    local status=0
    "$SL" compare "$2" "$3" --metric p99rel --tolerance 0.05 >"$T/$1.txt" || status=$?
    printf '%-18s p99 rel %-10s mean rel %-10s max abs %-10s >1/255 %s%%  >8/255 %s%%\n' "$1" \
        "$(gl_field "p99 rel error" "$T/$1.txt")" "$(gl_field "mean rel error" "$T/$1.txt")" \
        "$(gl_field "max abs error" "$T/$1.txt")" "$(gl_field "8-bit diff > 1" "$T/$1.txt")" \
        "$(gl_field "8-bit diff > 8" "$T/$1.txt")"
    [ "$status" = 0 ] && gl_check_share "$1" "$T/$1.txt" 0.1
}

# gl_outside NAME A B WHY: the case must fail gl_within (a GL image that leaves out what C's has,
# the test's proof that it can see the feature); otherwise print "FAIL WHY" and return 1.
gl_outside() {
    if gl_within "$1" "$2" "$3" >/dev/null; then
        echo "FAIL $4"
        return 1
    fi
}

# gl_compare_estimator NAME SCENE ESTIMATOR P99_TOL OVER8_PERCENT [options...]: render SCENE with
# --estimator ESTIMATOR and the options through softlight (at GL_TEST_SIZE, with its G-buffer) and
# through softlight-gl on that G-buffer, print the comparison's line, and return 1 unless the p99
# relative error is <= P99_TOL and the share more than 8/255 apart <= OVER8_PERCENT. The
# estimators' GL tests (gl_splitsum.sh, gl_mis.sh, gl_cv.sh) each run it per case.
gl_compare_estimator() {
    local name=$1 scene=$2 estimator=$3 p99=$4 over8=$5
    shift 5
    mkdir -p "$T/$name"
    "$SL" render "$scene" --estimator "$estimator" "$@" --size "$GL_TEST_SIZE" --aov "$T/$name" --pfm "$T/$name/c.pfm" >/dev/null
    "$GL" render "$scene" --estimator "$estimator" "$@" --gbuffer "$T/$name" --pfm "$T/$name/g.pfm" >/dev/null
    local status=0
    "$SL" compare "$T/$name/c.pfm" "$T/$name/g.pfm" --metric p99rel --tolerance "$p99" >"$T/$name.txt" || status=$?
    printf '%-14s p99 rel %-10s mean rel %-10s max abs %-10s >8/255 %s%%\n' "$name" \
        "$(gl_field "p99 rel error" "$T/$name.txt")" "$(gl_field "mean rel error" "$T/$name.txt")" \
        "$(gl_field "max abs error" "$T/$name.txt")" "$(gl_field "8-bit diff > 8" "$T/$name.txt")"
    if [ "$status" != 0 ]; then
        echo "FAIL $name: $(grep -E '^(PASS|FAIL)' "$T/$name.txt")"
        grep '^worst' "$T/$name.txt" || true
        gl_check_share "$name" "$T/$name.txt" "$over8" || true
        return 1
    fi
    gl_check_share "$name" "$T/$name.txt" "$over8"
}

# gl_bound DIFF CHANNEL GROUP MAX SHARE: a line of tests/cli/gbuffer_diff.py's output (channel,
# group, pixels, max, share > 1/255) must exist and stay within MAX and SHARE; sets fail=1 if not.
gl_bound() {
    awk -v c="$2" -v g="$3" -v m="$4" -v s="$5" '$1 == c && $2 == g {
        found = 1
        if ($4 > m || $5 > s) { printf "FAIL %s (%s): max %s (allowed %s), share %s (allowed %s)\n", c, g, $4, m, $5, s; exit 1 }
    } END { if (!found) { printf "FAIL %s (%s): not measured\n", c, g; exit 1 } }' "$1" || fail=1
}
