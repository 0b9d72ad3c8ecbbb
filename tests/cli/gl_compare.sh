#!/usr/bin/env bash
# gl_compare.sh BUILD_DIR - `softlight compare` as scripts use it: exit 0 within the tolerance, 1
# outside it, 2 on errors; the difference image is written. Needs no GL: the images are tiny PFMs
# written byte by byte here (little-endian float32, bottom row first), so the values are exact.
set -euo pipefail
cd "$(dirname "$0")/../.."
SL=${1:?usage: $0 BUILD_DIR}/softlight
T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-compare-test.XXXXXX")
trap 'rm -rf "$T"' EXIT

# pfm FILE W H BYTES...: a 1-channel PFM; each float given as its 4 little-endian bytes in hex.
pfm() {
    local file=$1 w=$2 h=$3
    shift 3
    printf 'Pf\n%d %d\n-1.0\n' "$w" "$h" >"$file"
    for f in "$@"; do printf "$f" >>"$file"; done
}
ONE='\x00\x00\x80\x3f'      # 1.0
ONE_HALF='\x00\x00\xc0\x3f' # 1.5
ZERO='\x00\x00\x00\x00'
pfm "$T/a.pfm" 2 1 "$ONE" "$ONE"
pfm "$T/b.pfm" 2 1 "$ONE" "$ONE_HALF"
pfm "$T/m.pfm" 2 1 "$ONE" "$ZERO"
pfm "$T/c.pfm" 1 1 "$ONE"

fail=0
# expect STATUS ARGS...: run `softlight compare ARGS` and check its exit status.
expect() {
    local want=$1 got=0
    shift
    "$SL" compare "$@" >"$T/out.txt" 2>&1 || got=$?
    if [ "$got" != "$want" ]; then
        echo "FAIL: softlight compare $* exited $got, expected $want"
        cat "$T/out.txt"
        fail=1
    else
        echo "ok: exit $got: compare $*" | sed "s|$T/||g"
    fi
}
# the one difference is 0.5: max 0.5, rmse sqrt(0.25 / 2) = 0.3536
expect 0 "$T/a.pfm" "$T/b.pfm" --metric max --tolerance 0.5
expect 1 "$T/a.pfm" "$T/b.pfm" --metric max --tolerance 0.49
expect 0 "$T/a.pfm" "$T/b.pfm" --metric rmse --tolerance 0.354
expect 1 "$T/a.pfm" "$T/b.pfm" --metric rmse --tolerance 0.353
# masked out, the difference is gone
expect 0 "$T/a.pfm" "$T/b.pfm" --mask "$T/m.pfm" --metric max --tolerance 0
expect 0 "$T/a.pfm" "$T/b.pfm" --diff "$T/diff.png"
[ -s "$T/diff.png" ] || { echo "FAIL: no difference image"; fail=1; }
expect 2 "$T/a.pfm" "$T/c.pfm"
expect 2 "$T/a.pfm" "$T/missing.pfm"
expect 2 "$T/a.pfm" "$T/b.pfm" --metric median
expect 2 "$T/a.pfm"
grep -q '^max abs error   0.5$' <("$SL" compare "$T/a.pfm" "$T/b.pfm") || { echo "FAIL: max abs error not printed as 0.5"; fail=1; }
[ "$fail" = 0 ] && echo "gl_compare: all exit statuses as documented"
exit "$fail"
