#!/usr/bin/env bash
# exr.sh BUILD_DIR - OpenEXR end to end: `render --exr` writes the radiance and every G-buffer
# channel as layers holding the same numbers as --pfm and --aov (compared with max error 0);
# that radiance read back as an environment (--env, and the scene key environment.hdr) renders
# the same PNG, byte for byte, as the same floats in a PFM; truncated, corrupt and wrong-type
# .exr files each give one line naming the file and exit 2, leaving outputs untouched.
set -u
. "$(dirname "$0")/lib.bash"
cli_init exr "$@"

# 1. The layers against the PFMs: every AOV and the radiance, max error 0.
"$SL" render scenes/default.json --size 96x54 -n 8 --exr "$T/frame.exr" --aov "$T/aov" --pfm "$T/frame.pfm" -q
for layer in position normal view kd ks alpha depth mask; do
    if "$SL" compare "$T/frame.exr:$layer" "$T/aov/$layer.pfm" --metric max --tolerance 0 >"$T/out" 2>&1; then
        ok "layer $layer equals $layer.pfm"
    else
        bad "layer $layer differs from $layer.pfm:"; tail -3 "$T/out"
    fi
done
if "$SL" compare "$T/frame.exr" "$T/frame.pfm" --metric max --tolerance 0 >"$T/out" 2>&1; then
    ok "R, G, B equal the --pfm radiance"
else
    bad "R, G, B differ from the --pfm radiance:"; tail -3 "$T/out"
fi

# 2. That radiance as an environment: the .exr and the .pfm (the same floats) give one PNG.
"$SL" render scenes/bunny.json --size 64x36 -n 4 --env "$T/frame.exr" -o "$T/env-exr.png" -q
"$SL" render scenes/bunny.json --size 64x36 -n 4 --env "$T/frame.pfm" -o "$T/env-pfm.png" -q
if cmp -s "$T/env-exr.png" "$T/env-pfm.png"; then ok "--env frame.exr renders as --env frame.pfm"; else bad "--env .exr and .pfm differ"; fi
printf '{"environment": {"hdr": "%s"}, "objects": [{"shape": "sphere"}], "render": {"width": 32, "height": 18, "samples": 4}}\n' \
    "$T/frame.exr" >"$T/scene-exr.json"
sed "s/frame.exr/frame.pfm/" "$T/scene-exr.json" >"$T/scene-pfm.json"
"$SL" render "$T/scene-exr.json" -o "$T/key-exr.png" -q && "$SL" render "$T/scene-pfm.json" -o "$T/key-pfm.png" -q
if cmp -s "$T/key-exr.png" "$T/key-pfm.png"; then ok "environment.hdr: frame.exr renders as frame.pfm"; else bad "environment.hdr: .exr and .pfm differ"; fi

# 3. Bad files: one line naming the file, status 2, the existing output untouched.
size=$(stat -c %s "$T/frame.exr")
head -c $((size / 2)) "$T/frame.exr" >"$T/truncated.exr"
head -c 6 "$T/frame.exr" >"$T/short.exr"
cp "$T/frame.exr" "$T/corrupt.exr"
printf '\377\377\377\377\377\377\377\377' | dd of="$T/corrupt.exr" bs=1 seek=$((size - 2000)) conv=notrunc status=none
printf 'not an exr at all\n' >"$T/text.exr"
mkfifo "$T/fifo.exr"
echo keep >"$T/keep.png"
expect_error "truncated .exr" "truncated.exr: .*OpenEXR" -- "$SL" render scenes/bunny.json --env "$T/truncated.exr" -o "$T/keep.png"
expect_error "six bytes" "short.exr: " -- "$SL" render scenes/bunny.json --env "$T/short.exr" -o "$T/keep.png"
expect_error "corrupt chunk" "corrupt.exr: " -- "$SL" render scenes/bunny.json --env "$T/corrupt.exr" -o "$T/keep.png"
expect_error "text named .exr" "text.exr: byte 0: not an OpenEXR file" -- "$SL" render scenes/bunny.json --env "$T/text.exr" -o "$T/keep.png"
expect_error "FIFO named .exr" "fifo.exr: not a regular file" -- "$SL" render scenes/bunny.json --env "$T/fifo.exr" -o "$T/keep.png"
if [ "$(cat "$T/keep.png")" = keep ]; then ok "outputs untouched after the errors"; else bad "keep.png was replaced"; fi

echo "exr.sh: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
