#!/usr/bin/env bash
# truth_visibility.sh BUILD_DIR - `softlight truth --visibility` and `--lights` end to end: the
# cache key tells visibility, its level and the point lights apart; visibility only takes light
# away (every pixel at most its blind value) and darkens the floor under the bunny; shards merge
# to the unsharded bytes; a scene's ambient occlusion is left off with visibility; bad
# combinations are one line and status 2. In a build without Embree
# the whole test is the refusal: one line, status 2.
set -u
. "$(dirname "$0")/lib.bash"
cli_init truth_visibility "$@"
scene=scenes/bunny.json
SIZE=24x14

if ! "$SL" truth "$scene" --size 2x2 --visibility --pfm "$T/probe.pfm" >/dev/null 2>"$T/probe.err"; then
    expect_error "no Embree" "needs Embree 3" -- "$SL" truth "$scene" --size 2x2 --visibility --pfm "$T/x.pfm"
    cli_done "truth_visibility (a build without Embree)"
    exit
fi

"$SL" truth "$scene" --size $SIZE --visibility --cache "$T/c" --parts "$T/v" --pfm "$T/v.pfm" >"$T/1.txt" 2>/dev/null
grep -q "visibility: integrated" "$T/1.txt" && ok "visibility integrated: $(grep rays "$T/1.txt")" || bad "first run: $(cat "$T/1.txt")"
grep -q " 0 pixels without a geometric normal" "$T/1.txt" && ok "every pixel has its geometric normal" || bad "fallbacks: $(cat "$T/1.txt")"
"$SL" truth "$scene" --size $SIZE --visibility --cache "$T/c" --pfm "$T/v2.pfm" >"$T/2.txt" 2>/dev/null
grep -q "read from the cache" "$T/2.txt" && cmp -s "$T/v.pfm" "$T/v2.pfm" && ok "second run read the cache, same bytes" ||
    bad "second run: $(cat "$T/2.txt")"
for other in "" "--visibility --vis-level 2" "--visibility --lights"; do
    cp "$T/c" "$T/c2" # the visibility truth's cache, offered to another setting
    # shellcheck disable=SC2086
    "$SL" truth "$scene" --size $SIZE $other --cache "$T/c2" --parts "$T/o${other:+-x}" >"$T/3.txt" 2>/dev/null
    grep -q "integrated" "$T/3.txt" && ok "'${other:-blind}' is another key: integrated" || bad "'${other:-blind}' read a cache of another setting"
done
mv "$T/o" "$T/b" # the blind truth's parts

# visibility takes light away and never adds it; the shadow under the bunny is deep
python3 - "$T/v/diffuse.pfm" "$T/b/diffuse.pfm" >"$T/cmp.txt" <<'EOF' && ok "$(cat "$T/cmp.txt")" || bad "$(cat "$T/cmp.txt")"
import struct, sys
def pfm(path):
    with open(path, 'rb') as f:
        kind = f.readline().strip(); w, h = map(int, f.readline().split()); scale = float(f.readline())
        n = w * h * (3 if kind == b'PF' else 1)
        return struct.unpack(('<' if scale < 0 else '>') + 'f' * n, f.read(4 * n))
vis, blind = pfm(sys.argv[1]), pfm(sys.argv[2])
over = [i for i, (a, b) in enumerate(zip(vis, blind)) if a > b * (1 + 1e-5) + 1e-7]
ratios = sorted(a / b for a, b in zip(vis[1::3], blind[1::3]) if b > 0)  # green, per pixel
darker = sum(1 for r in ratios if r < 0.7)
if over or darker < 3 or ratios[0] > 0.6:
    print(f"visibility against blind: {len(over)} values above blind (first {over[:3]}), {darker} pixels "
          f"below 0.7 of it, the darkest at {ratios[0]:.3f}")
    sys.exit(1)
print(f"visibility never above blind; {darker} pixels below 0.7 of it (the shadow), the darkest at {ratios[0]:.3f}")
EOF

# shards merge to the unsharded bytes
for i in 1 2; do
    "$SL" truth "$scene" --size $SIZE --visibility --pfm "$T/s.pfm" --shard $i/2 >/dev/null 2>&1
done
"$SL" merge "$T"/s.pfm.shard-*-of-2 >/dev/null 2>&1 && cmp -s "$T/s.pfm" "$T/v.pfm" &&
    ok "2 shards merge to the unsharded truth" || bad "sharded visibility truth differs"

# a scene's ambient occlusion (render.ao_radius, GTAO) is left off with --visibility (traced
# visibility replaces it): the same bytes as without it; the blind truth keeps it, as the render does
python3 - "$scene" "$T/ao.json" <<'EOF'
import json, os, sys
d = json.load(open(sys.argv[1])); base = os.path.dirname(os.path.abspath(sys.argv[1]))
d["environment"]["hdr"] = os.path.join(base, d["environment"]["hdr"])
for o in d["objects"]:
    if "mesh" in o: o["mesh"] = os.path.join(base, o["mesh"])
d["render"]["ao_radius"] = 0.5
json.dump(d, open(sys.argv[2], "w"))
EOF
"$SL" truth "$T/ao.json" --size $SIZE --visibility --pfm "$T/ao-v.pfm" >/dev/null 2>&1
"$SL" truth "$T/ao.json" --size $SIZE --parts "$T/ao-b" >/dev/null 2>&1
cmp -s "$T/ao-v.pfm" "$T/v.pfm" && ok "--visibility leaves the scene's ambient occlusion off" ||
    bad "--visibility on a scene with ao_radius differs from the scene without it"
[ -f "$T/ao-b/diffuse.pfm" ] && ! cmp -s "$T/ao-b/diffuse.pfm" "$T/b/diffuse.pfm" &&
    ok "the blind truth keeps the scene's ambient occlusion" || bad "the blind truth ignored ao_radius"

expect_error "--vis-level alone" "needs --visibility" -- "$SL" truth "$scene" --size 2x2 --vis-level 2
expect_error "--vis-level out of range" "vis-level" -- "$SL" truth "$scene" --size 2x2 --visibility --vis-level 9
cli_done truth_visibility
