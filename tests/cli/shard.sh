#!/usr/bin/env bash
# shard.sh BUILD_DIR - `--shard I/N` and `softlight merge`: shards run as separate processes with
# GNU parallel (standing in for hosts), merged, give byte for byte the files of the unsharded
# command, for render on every shipped scene (PNG, .pfm, .hdr, AOVs, normals), with the sky maps,
# and for truth; bad sets of partials are refused with one line, exit 2, and nothing written.
set -euo pipefail
cd "$(dirname "$0")/../.."
SL="$(cd "$1" && pwd)/softlight"
command -v parallel >/dev/null || { echo "FAIL: GNU parallel missing (scripts/setup.sh installs it)"; exit 1; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

for scene in scenes/*.json; do
  s=$(basename "$scene" .json)
  "$SL" render "$scene" --size 80x45 -n 8 -q -o "$T/$s.png" --pfm "$T/$s.pfm" --hdr "$T/$s.hdr" --aov "$T/$s-aov" \
    --normals "$T/$s-n.png"
  parallel "$SL" render "$scene" --size 80x45 -n 8 -q -o "$T/m-$s.png" --pfm "$T/m-$s.pfm" --hdr "$T/m-$s.hdr" \
    --aov "$T/m-$s-aov" --normals "$T/m-$s-n.png" --shard {}/3 -j 1 ::: 1 2 3
  "$SL" merge -q "$T"/m-$s.png.shard-*-of-3
  for f in $s.png $s.pfm $s.hdr $s-n.png $s-aov/position.pfm $s-aov/normal.pfm $s-aov/mask.pfm $s-aov/depth.pfm; do
    cmp -s "$T/$f" "$T/m-$f" || fail "$scene: merged $f differs from the unsharded one"
  done
done

# the sky maps' plane fills a texel from the rows beside it: a shard's edge rows too
"$SL" render scenes/default.json --size 80x45 -n 8 -q --sky-maps 32 --pfm "$T/sky.pfm" -o "$T/sky.png"
parallel "$SL" render scenes/default.json --size 80x45 -n 8 -q --sky-maps 32 --pfm "$T/m-sky.pfm" -o "$T/m-sky.png" \
  --shard {}/3 -j 1 ::: 1 2 3
"$SL" merge -q "$T"/m-sky.png.shard-*-of-3
cmp -s "$T/sky.pfm" "$T/m-sky.pfm" || fail "--sky-maps 32: merged radiance differs from the unsharded one"

# truth: 4 shards, one of them empty of geometry is fine; 45 rows over 4 shards
scene=scenes/default.json
"$SL" truth "$scene" --size 24x14 --pfm "$T/t.pfm" -o "$T/t.png" --parts "$T/tp" >/dev/null 2>&1
parallel "$SL" truth "$scene" --size 24x14 --pfm "$T/mt.pfm" -o "$T/mt.png" --parts "$T/mtp" --shard {}/4 \
  --partial "$T/truth.{}" ::: 1 2 3 4 >/dev/null 2>&1
"$SL" merge -q "$T"/truth.[1-4]
for f in t.pfm t.png tp/diffuse.pfm tp/specular-one.pfm tp/mask.pfm; do
  cmp -s "$T/$f" "$T/m$f" || fail "truth: merged $f differs"
done

# bad sets: one line, exit 2, nothing written
cd "$T"
bad() { # bad WHAT EXPECTED-WORDS FILES...
  local what=$1 words=$2; shift 2
  rm -f bad.png
  set +e; "$SL" merge "$@" >out.txt 2>err.txt; st=$?; set -e
  [ $st = 2 ] || fail "$what: exit $st, expected 2"
  [ "$(wc -l <err.txt)" = 1 ] || fail "$what: not one line: $(cat err.txt)"
  grep -q "$words" err.txt || fail "$what: message lacks '$words': $(cat err.txt)"
  [ ! -e bad.png ] || fail "$what: wrote an output"
}
"$SL" render "$OLDPWD/$scene" --size 40x20 -n 4 -q -o bad.png --shard 1/2
"$SL" render "$OLDPWD/$scene" --size 40x20 -n 4 -q -o bad.png --shard 2/2
"$SL" render "$OLDPWD/$scene" --size 40x20 -n 4 -q -o bad.png --shard 2/2 -e 2 --partial other.2
bad "missing shard" "shard 2 of 2 is missing" bad.png.shard-1-of-2
bad "duplicate" "also in" bad.png.shard-1-of-2 bad.png.shard-1-of-2 bad.png.shard-2-of-2
bad "other options" "not a shard of the same run" bad.png.shard-1-of-2 other.2
head -c 2000 bad.png.shard-2-of-2 >trunc.2
bad "truncated" "truncated" bad.png.shard-1-of-2 trunc.2
echo "hello" >notpart.2
bad "not a partial" "not a softlight partial" bad.png.shard-1-of-2 notpart.2
"$SL" merge -q bad.png.shard-1-of-2 bad.png.shard-2-of-2
[ -s bad.png ] || fail "the good pair did not merge"
echo "shard: OK"
