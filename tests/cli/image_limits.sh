#!/usr/bin/env bash
# image_limits.sh BUILD_DIR - hostile images end to end: a small .hdr
# declaring 16384x8192 is refused under the image memory budget before anything that size is
# allocated (run under `ulimit -v`, so an allocation would fail the test instead of the machine),
# naming --image-memory; /dev/zero as an environment fails on its first bytes; a header without
# its blank line is reported at byte 34; and `softlight info`'s peak memory agrees with the
# measured maximum resident set size of the render it describes.
set -u
. "$(dirname "$0")/lib.bash"
cli_init limits "$@"

# expect_error NAME PATTERN -- COMMAND...: status 2, one stderr line matching PATTERN, < 5 s.
expect_error() {
    local name=$1 pattern=$2; shift 3
    local t0=$SECONDS secs
    one_error "$pattern" "$@"
    local matched=$?
    secs=$((SECONDS - t0))
    if [ "$matched" -ne 0 ] || [ "$secs" -ge 5 ]; then
        bad "$name: status $err_status, $err_lines stderr lines, ${secs} s (want 2, 1 matching /$pattern/, < 5 s):"
        sed 's/^/    /' "$T/err" | head -5
    else
        ok "$name: $(cat "$T/err")"
    fi
}

# An RLE .hdr of W x H, every component one run per 127 pixels.
rle_hdr() { # rle_hdr FILE W H [no-blank]
    python3 - "$@" <<'PY'
import sys
path, W, H = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
blank = b'' if len(sys.argv) > 4 else b'\n'
r = b''.join(bytes([128 + min(127, W - i), 130]) for i in range(0, W, 127))
with open(path, 'wb') as f:
    f.write(b'#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n' + blank + b'-Y %d +X %d\n' % (H, W))
    f.write((bytes([2, 2, W >> 8, W & 255]) + r * 4) * H)
PY
}
scene() { # scene FILE HDR [WxH]
    local size=${3:-64x36}
    printf '{"environment": {"hdr": "%s"}, "objects": [{"shape": "sphere"}], "render": {"width": %d, "height": %d, "samples": 4}}\n' \
        "$2" "${size%x*}" "${size#*x}" >"$1"
}

# Under the sanitizers (SL_SANITIZED=1) ulimit -v would stop ASan's shadow memory: its allocator
# gets the same 1 GiB cap instead, and the RSS comparison (ASan's overhead) is skipped.
if [ -n "${SL_SANITIZED:-}" ]; then
    export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}max_allocation_size_mb=1024:allocator_may_return_null=1"
    LIMIT=:
else
    LIMIT='ulimit -v 1048576'
fi

rle_hdr "$T/bomb.hdr" 16384 8192
rle_hdr "$T/noblank.hdr" 1024 512 no-blank
rle_hdr "$T/mid.hdr" 2048 1024
scene "$T/bomb.json" bomb.hdr 320x180
scene "$T/noblank.json" noblank.hdr
scene "$T/zero.json" /dev/zero
scene "$T/mid.json" mid.hdr

# The bomb: 8.5 MB declaring 1.5 GiB of floats (6.5 GiB at the render's peak). Under a 1 GiB
# address-space limit a reader that allocated first would fail with "out of memory" instead.
expect_error bomb-render 'bomb\.hdr: byte 35: image 16384x8192 needs 1536 MiB.*budget of 1024 MiB.*--image-memory 1536' -- \
    bash -c "$LIMIT"'; exec "$0" "$@"' "$SL" render "$T/bomb.json" -o "$T/a.png"
expect_error bomb-info 'bomb\.hdr: byte 35: .*--image-memory 1536' -- \
    bash -c "$LIMIT"'; exec "$0" "$@"' "$SL" info "$T/bomb.json"
expect_error bomb-small-budget 'mid\.hdr: byte 35: image 2048x1024 needs 24 MiB.*budget of 8 MiB' -- \
    "$SL" render "$T/mid.json" --image-memory 8 -o "$T/a.png"
expect_error budget-range '--image-memory' -- "$SL" render "$T/mid.json" --image-memory 0 -o "$T/a.png"
expect_error dev-zero '/dev/zero: byte 0: not a Radiance \.hdr file' -- \
    bash -c "$LIMIT"'; exec "$0" "$@"' "$SL" render "$T/zero.json" -o "$T/a.png"
expect_error no-blank-line 'noblank\.hdr: byte 34: found the resolution line .-Y 512 \+X 1024. in the header' -- \
    "$SL" render "$T/noblank.json" -o "$T/a.png"
[ -e "$T/a.png" ] && bad "a failed render left a.png behind"

# info's peak against the measured peak (max RSS) of the same render, within 12%: the default
# render, the two modes that hold a second chain (split sum's prefiltered chain with its pair
# rows, the octahedral chain), a point light's cube shadow map (scenes/lamp.json --shadows), 64
# sky visibility maps (64 MiB), and the ambient and reflection occlusion's planes.
if [ -z "${SL_SANITIZED:-}" ]; then
    for case in "$T/mid.json|" "$T/mid.json|--estimator splitsum" "$T/mid.json|--env-layout oct" \
                "scenes/lamp.json|--shadows" "$T/mid.json|--sky-maps 64" \
                "$T/mid.json|--ao-radius 1 --reflection-occlusion 5"; do
        scene=${case%%|*} modes=${case#*|}
        # shellcheck disable=SC2086 # $modes is zero or more words
        peak=$("$SL" info "$scene" $modes | sed -n 's/.*memory     peak \([0-9.]*\) MiB.*/\1/p')
        # shellcheck disable=SC2086
        rss=$(/usr/bin/time -f '%M' "$SL" render "$scene" $modes -o "$T/mid.png" 2>&1 >/dev/null | tail -n 1 |
              awk '{ printf "%.1f", $1 / 1024 }')
        if [ -n "$peak" ] && [ -n "$rss" ] && awk -v p="$peak" -v r="$rss" 'BEGIN { d = p - r; if (d < 0) d = -d; exit !(d <= 0.12 * r) }'; then
            ok "info's peak $peak MiB against a measured $rss MiB (${modes:-default modes})"
        else
            bad "info's peak '$peak' MiB against a measured '$rss' MiB (${modes:-default modes}; want within 12%)"
        fi
    done
fi
# and with a raised budget, the same file passes info
if "$SL" info "$T/mid.json" --image-memory 24 >/dev/null 2>&1; then ok "--image-memory 24 reads the 24 MiB map"
else bad "--image-memory 24 did not read the 24 MiB map"; fi
echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
