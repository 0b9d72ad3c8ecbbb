#!/usr/bin/env bash
# maps.sh BUILD_DIR - the maps a reader navigates by stay true:
#   includes  every `#include "..."` in src/ runs down the layers of docs/architecture.md "Layers"
#             (its own folder, the public softlight/ headers, or a folder on a lower layer);
#   docs      every `docs/NAME.md "Section"` reference in the tree resolves (scripts/check-docs.py);
#   tags      the C port follows shaders/lighting.frag: each `/* GLSL: name` tag in src/shading
#             (and src/shadow's files, the shadow lookup, and src/occlusion's, the specular and
#             reflection occlusion) names a function of lighting.frag,
#             each file's tags come in lighting.frag's order (a name may repeat right after
#             itself: one GLSL function in several C pieces), and every function of
#             lighting.frag is tagged in some such file. With no tag at all it says so and
#             passes; one tag makes it strict.
# Then it shows each check failing: it runs them on temporary copies with an include that runs
# up, a broken section reference, two swapped tags (and a few more), and expects each to fail.
# Runs from the source root; BUILD_DIR only says whether this is the sanitized suite, where the
# check is skipped: it reads the sources, not the build, and `make test`'s other suites run it.
set -u
if grep -q '^SL_SANITIZE:BOOL=ON' "${1:-/nonexistent}/CMakeCache.txt" 2>/dev/null; then
    echo "skip: the sources' maps do not depend on the build (the Release and clang suites check them)"
    exit 0
fi
cd "$(dirname "$0")/../.." || exit 2
src_root=$PWD
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }

# The Layers table of ROOT/docs/architecture.md as "FOLDER LAYER" lines.
layers() {
    awk '/^#+ /{ in_layers = ($0 ~ /^#+ Layers *$/) }
         in_layers && /^\| *[0-9]+ *\|/ {
             n = $0; sub(/^\| */, "", n); sub(/ *\|.*/, "", n)
             rest = $0; while (match(rest, /`[a-z0-9_]+`/)) {
                 print substr(rest, RSTART + 1, RLENGTH - 2), n; rest = substr(rest, RSTART + RLENGTH) } }' \
        "$1/docs/architecture.md"
}

# normalize PATH: PATH without its . and .. parts, into REPLY (in the shell: a realpath process
# per include took most of this test's time)
normalize() {
    local IFS=/ part
    local -a out=()
    for part in $1; do
        case $part in
        '' | .) ;;
        ..) [ ${#out[@]} -gt 0 ] && out=("${out[@]:0:${#out[@]}-1}") ;;
        *) out+=("$part") ;;
        esac
    done
    REPLY="${out[*]}"
}

# check_includes ROOT: prints one line per include that does not run down; status 1 if any.
check_includes() {
    local root=$1 bad=0 table f folder line inc target tf
    table=$(layers "$root")
    if [ -z "$table" ]; then echo "$root/docs/architecture.md: no Layers table"; return 1; fi
    declare -A layer=()
    while read -r f n; do layer[$f]=$n; done <<<"$table"
    for f in "$root"/src/*/; do
        f=$(basename "$f")
        [ -n "${layer[$f]:-}" ] || { echo "src/$f: a folder the Layers table does not place"; bad=1; }
    done
    for f in "${!layer[@]}"; do
        [ -d "$root/src/$f" ] || { echo "Layers table: $f is no folder of src/"; bad=1; }
    done
    while IFS=: read -r f line inc; do
        inc=${inc#*\"}; inc=${inc%%\"*}
        folder=${f#src/}; folder=${folder%%/*}
        case $inc in softlight/*) continue ;; esac
        normalize "${f%/*}/$inc"
        target=$REPLY
        [ -e "$root/$target" ] || target=src/$inc
        if [ ! -e "$root/$target" ]; then echo "$f:$line: #include \"$inc\" names no file"; bad=1; continue; fi
        case $target in src/*/*) ;; *) echo "$f:$line: #include \"$inc\" is outside src/'s folders"; bad=1; continue ;; esac
        tf=${target#src/}; tf=${tf%%/*}
        [ "$tf" = "$folder" ] && continue
        if [ -z "${layer[$folder]:-}" ] || [ -z "${layer[$tf]:-}" ] || [ "${layer[$tf]}" -ge "${layer[$folder]}" ]; then
            echo "$f:$line: #include \"$inc\": $folder (layer ${layer[$folder]:-?}) includes $tf (layer ${layer[$tf]:-?}), not below it"
            bad=1
        fi
    done < <(cd "$root" && grep -nE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' src/*/*.[ch])
    return $bad
}

# check_docs ROOT: the section references resolve.
check_docs() { python3 "$src_root/scripts/check-docs.py" "$1"; }
# check_tags ROOT: the GLSL tags of ROOT/src/shading (and src/shadow and src/occlusion, whose lookups
# lighting.frag ports too) against ROOT/shaders/lighting.frag.
check_tags() {
    local root=$1 bad=0 glsl tags f
    # lighting.frag's function definitions in file order (`TYPE name(` at the start of a line,
    # not a prototype).
    glsl=$(grep -E '^[A-Za-z_][A-Za-z0-9_]*( [A-Za-z_][A-Za-z0-9_]*)* [A-Za-z_][A-Za-z0-9_]*\(' "$root/shaders/lighting.frag" |
           grep -v ';[[:space:]]*$' | sed -E 's/^.* ([A-Za-z_][A-Za-z0-9_]*)\(.*/\1/' | awk '!seen[$0]++')
    if [ -z "$glsl" ]; then echo "shaders/lighting.frag: no functions found"; return 1; fi
    # lighting.c, the port, first; then the other files, headers included.
    local files=()
    [ -f "$root/src/shading/lighting.c" ] && files+=(src/shading/lighting.c)
    for f in "$root"/src/shading/*.[ch]; do
        f=src/shading/$(basename "$f"); [ "$f" = src/shading/lighting.c ] || files+=("$f")
    done
    for f in "$root"/src/shadow/*.[ch] "$root"/src/occlusion/*.[ch]; do
        [ -f "$f" ] && files+=("${f#"$root"/}")
    done
    tags=$(cd "$root" && grep -noE '/\* GLSL: [A-Za-z_][A-Za-z0-9_]*' "${files[@]}" /dev/null | sed 's|/\* GLSL: ||')
    if [ -z "$tags" ]; then echo "no GLSL tags in src/shading yet: order not checked"; return 0; fi
    awk -F: -v glsl="$glsl" '
        BEGIN { n = split(glsl, g, "\n"); for (i = 1; i <= n; i++) at[g[i]] = i }
        {   file = $1; line = $2; name = $3; tagged[name] = 1
            if (!(name in at)) { print file ":" line ": GLSL: " name " is no function of shaders/lighting.frag"; bad = 1; next }
            if (file == last_file && at[name] < last_at)
                { print file ":" line ": GLSL: " name " after GLSL: " last_name " (line " last_line "); lighting.frag has them the other way round"; bad = 1 }
            last_file = file; last_at = at[name]; last_name = name; last_line = line }
        END { for (i = 1; i <= n; i++) if (!(g[i] in tagged)) { print "GLSL function " g[i] " (shaders/lighting.frag) has no GLSL: tag in src/shading, src/shadow or src/occlusion"; bad = 1 }
              exit bad }' <<<"$tags"
}

# ---- the tree itself ----
out=$(check_includes "$src_root") || fail "includes that do not run down the layers:"$'\n'"$out"
out=$(check_docs "$src_root") || fail "documentation references that do not resolve:"$'\n'"$out"
out=$(check_tags "$src_root") || fail "GLSL tags that do not follow shaders/lighting.frag:"$'\n'"$out"
[ -n "$out" ] && [ "$fails" -eq 0 ] && echo "$out"

# ---- each check fails when it should ----
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
expect() { # expect pass|fail WHAT CHECK ROOT
    local want=$1 what=$2 got=pass; shift 2
    "$@" >"$tmp/out" 2>&1 || got=fail
    [ "$got" = "$want" ] || fail "self-test: $what: expected $want, got $got: $(head -c 600 "$tmp/out")"
}

# includes: a copy of src/ and the doc, then an include up, one across a layer, an unplaced folder
inc=$tmp/inc
mkdir -p "$inc/docs" && cp -r src "$inc/" && cp docs/architecture.md "$inc/docs/"
expect pass "includes on an unchanged copy" check_includes "$inc"
echo '#include "../app/args.h"' >>"$inc/src/core/error.c"
expect fail "core including app" check_includes "$inc"
cp src/core/error.c "$inc/src/core/error.c"
echo '#include "../ibl/ibl.h"' >>"$inc/src/scene/obj.c"
expect fail "scene including ibl, its own layer" check_includes "$inc"
cp src/scene/obj.c "$inc/src/scene/obj.c"
echo '#include "no_such_header.h"' >>"$inc/src/post/tonemap.c" 2>/dev/null || true
expect fail "an include that names no file" check_includes "$inc"
rm -rf "$inc/src/post" && cp -r src/post "$inc/src/"
sed -i '/^| 6 | `post` |$/d' "$inc/docs/architecture.md"
expect fail "a folder missing from the Layers table" check_includes "$inc"

# docs: a small repository with the doc and a file citing a section it has, then one it lacks
doc=$tmp/doc
mkdir -p "$doc" && cp -r docs "$doc/" && git -C "$doc" init -q
cite() { printf '/* see docs/%s "%s" */\n' "$1" "$2" >"$doc/a.c"; } # spelt so that this file cites nothing
cite architecture.md "Call cycles"
expect pass "a section reference that resolves" check_docs "$doc"
cite architecture.md "No such section"
expect fail "a broken section reference" check_docs "$doc"

# tags: a port tagging every lighting.frag function in order, then two swapped, one unknown,
# one missing, and none at all
tag=$tmp/tag
mkdir -p "$tag/shaders" "$tag/src/shading" && cp shaders/lighting.frag "$tag/shaders/"
names=$(grep -E '^[A-Za-z_][A-Za-z0-9_]*( [A-Za-z_][A-Za-z0-9_]*)* [A-Za-z_][A-Za-z0-9_]*\(' shaders/lighting.frag |
        grep -v ';[[:space:]]*$' | sed -E 's/^.* ([A-Za-z_][A-Za-z0-9_]*)\(.*/\1/' | awk '!seen[$0]++')
port() { for n in "$@"; do printf '/* GLSL: %s */\nstatic void c_%s(void) {}\n' "$n" "$n"; done >"$tag/src/shading/lighting.c"; }
mapfile -t list <<<"$names"
port "${list[@]}"
printf '/* GLSL: %s */\n/* GLSL: %s */\n' "${list[2]}" "${list[5]}" >"$tag/src/shading/lighting_batched.c"
expect pass "tags in lighting.frag's order" check_tags "$tag"
port "${list[@]:0:3}" main main
expect fail "a function left untagged" check_tags "$tag"
port "${list[@]}" main
expect pass "main in pieces" check_tags "$tag"
port "${list[1]}" "${list[0]}" "${list[@]:2}"
expect fail "two swapped tags" check_tags "$tag"
port "${list[@]}" not_in_the_shader
expect fail "a tag naming no GLSL function" check_tags "$tag"
port "${list[@]}"
printf '/* GLSL: %s */\n/* GLSL: %s */\n' "${list[5]}" "${list[2]}" >"$tag/src/shading/lighting_batched.c"
expect fail "two swapped tags in another file" check_tags "$tag"
printf 'static void f(void) {}\n' >"$tag/src/shading/lighting.c"
printf 'static void g(void) {}\n' >"$tag/src/shading/lighting_batched.c"
expect pass "no tags at all" check_tags "$tag"

[ "$fails" -eq 0 ] && echo "maps: includes, documentation references and GLSL tags are true"
[ "$fails" -eq 0 ]
