#!/usr/bin/env bash
# same-output.sh BASE_BUILD NEW_BUILD - for changes that must not change behaviour (refactors):
# renders every shipped scene with both builds in every lighting mode and compares the files
# byte for byte: tone-mapped PNG, radiance (.hdr, .pfm), G-buffer AOVs, normals, a pixel trace,
# softlight-gl's image where both builds have it, and a small ground truth per scene. Prints one line per difference; exit 1 if any.
set -euo pipefail
if [ $# -ne 2 ] || [ "${1#-}" != "$1" ]; then
  echo "usage: scripts/same-output.sh BASE_BUILD NEW_BUILD (SIZE=WxH, default 160x90)" >&2
  exit 2
fi
base=$1 new=$2
size=${SIZE:-160x90}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
modes=(
  ""
  "--plain"
  "--estimator consistent --lod spec --g one"
  "--estimator mf --lod pdf --distortion --env-lights 8"
  "--estimator mf --lod gems --rotate --frame 3 -n 16"
  "--irradiance brute --diffuse-only"
  "--specular-only --no-lights --srgb -e 2 -c 1.3"
  "--lod none -n 7 --env-lights 3 --plain"
  "--estimator splitsum"
  "--estimator splitsum --irradiance sh9 --no-lights"
  "--estimator splitsum --irradiance dp --env-layout oct"
  "--estimator splitsum --irradiance brute --rotate"
  "--shadows --ao-radius 0.5"
  "--shadows --env-lights 8 --ao-radius 0.5 --estimator mf"
)
differ=0
run_both() {  # run_both NAME ARGS...: run ARGS with each build into $work/{base,new}/NAME
  local name=$1; shift
  for side in base new; do
    local b=$base; [ $side = new ] && b=$new
    local d=$work/$side/$name
    mkdir -p "$d"
    (cd "$d" && "$@" >"$d/stdout" 2>&1 || echo "exit $?" >>"$d/stdout") || true
  done
}
for scene in scenes/*.json; do
  s=$(basename "$scene" .json)
  i=0
  for m in "${modes[@]}"; do
    i=$((i + 1))
    for side in base new; do
      b=$base; [ $side = new ] && b=$new
      d=$work/$side/$s-$i; mkdir -p "$d"
      # shellcheck disable=SC2086
      "$b/softlight" render "$scene" --size "$size" -q $m -o "$d/out.png" --hdr "$d/out.hdr" \
        --pfm "$d/out.pfm" --aov "$d/aov" --normals "$d/normals.png" >"$d/log" 2>&1 || echo "exit $?" >>"$d/log"
      # shellcheck disable=SC2086
      "$b/softlight" trace "$scene" --size "$size" $m --pixel 80,40 >"$d/trace.txt" 2>&1 || echo "exit $?" >>"$d/trace.txt"
      if [ "$i" -eq 1 ]; then
        "$b/softlight" truth "$scene" --size 24x16 --pfm "$d/truth.pfm" >/dev/null 2>&1 || echo "exit $?" >>"$d/log"
      fi
      if [ -x "$b/softlight-gl" ] && [ "$i" -le 2 ]; then
        # its report line holds timings: only the error stream is compared
        "$b/softlight-gl" render "$scene" --size "$size" -o "$d/gl.png" --pfm "$d/gl.pfm" >/dev/null 2>"$d/gl.log" || echo "exit $?" >>"$d/gl.log"
      fi
    done
  done
done
for f in $(cd "$work/base" && find . -type f | sort); do
  if ! cmp -s "$work/base/$f" "$work/new/$f"; then
    echo "differs: $f"; differ=1
  fi
done
for f in $(cd "$work/new" && find . -type f | sort); do
  [ -e "$work/base/$f" ] || { echo "only in new: $f"; differ=1; }
done
n=$(cd "$work/base" && find . -type f | wc -l)
[ $differ -eq 0 ] && echo "same-output: $n files byte-identical"
exit $differ
