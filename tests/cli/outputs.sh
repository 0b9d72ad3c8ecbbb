#!/usr/bin/env bash
# outputs.sh BUILD_DIR - the files one command writes:
#  - all or nothing: when any output of `render` fails (--hdr, --pfm, --aov, --normals, -o, or the
#    disk filling up during the .pfm, simulated with `ulimit -f`), the command exits 2 with one
#    line and no existing output is replaced, no new one appears, no temporary is left;
#  - a symbolic link is written through (the link stays, its target gets the image), and a
#    target that is not a regular file (FIFO, directory, device behind a link) is refused in one
#    line and left as it was;
#  - a temporary left by a killed run (".NAME.softlight-tmp.PID" of a dead PID) is removed by the
#    next run writing NAME; one of a live process is not.
set -u
. "$(dirname "$0")/lib.bash"
cli_init outputs "$@"
fail() { bad "$@"; }

R=("$SL" render scenes/default.json --size 64x36 -n 4 -q)

# expect_error NAME PATTERN -- COMMAND...: status 2 and one stderr line matching PATTERN, in 120 s.
expect_error() {
    local name=$1 pattern=$2; shift 3
    if ! one_error "$pattern" timeout 120 "$@"; then
        fail "$name: status $err_status, $err_lines stderr lines (want 2, 1 matching /$pattern/): $(head -3 "$T/err" | tr '\n' ' ')"
        return 1
    fi
    ok "$name: $(cat "$T/err")"
}

# The outputs of the all-or-nothing cases live in $T/o; "old" files must keep their contents.
fresh_outputs() {
    rm -rf "$T/o"; mkdir -p "$T/o/aov"
    for f in o.png o.hdr o.pfm n.png aov/position.pfm; do echo old >"$T/o/$f"; done
}
# unchanged NAME: every old file still says "old", nothing else appeared (temporaries included).
unchanged() {
    local bad="" f
    for f in o.png o.hdr o.pfm n.png aov/position.pfm; do
        printf 'old\n' | cmp -s - "$T/o/$f" || bad="$bad $f"
    done
    local extra
    extra=$(cd "$T/o" && find . -mindepth 1 | sort | grep -vxE '\./(o\.png|o\.hdr|o\.pfm|n\.png|aov|aov/position\.pfm)' | tr '\n' ' ')
    if [ -n "$bad$extra" ]; then
        fail "$1: replaced:${bad:- none}; new files: ${extra:-none}"
    else
        ok "$1: no output replaced, nothing new"
    fi
}
ALL=(-o "$T/o/o.png" --hdr "$T/o/o.hdr" --pfm "$T/o/o.pfm" --aov "$T/o/aov" --normals "$T/o/n.png")

# ---- all outputs or none ----
for which in hdr pfm normals png; do
    fresh_outputs
    args=("${ALL[@]}")
    case $which in
    hdr) args+=(--hdr /nonexistent/x.hdr) ;;
    pfm) args+=(--pfm /nonexistent/x.pfm) ;;
    normals) args+=(--normals /nonexistent/n.png) ;;
    png) args+=(-o /nonexistent/o.png) ;;
    esac
    expect_error "bad --$which" "/nonexistent/" -- "${R[@]}" "${args[@]}"
    unchanged "bad --$which"
done
# --aov under a regular file: the directory cannot be made
fresh_outputs
echo file >"$T/plain"
expect_error "bad --aov" "plain/aov" -- "${R[@]}" "${ALL[@]}" --aov "$T/plain/aov"
unchanged "bad --aov"
# --aov into a new directory, another output failing: the directory made for it is removed too
fresh_outputs
expect_error "new --aov dir, bad --hdr" "/nonexistent/" -- "${R[@]}" "${ALL[@]}" --aov "$T/o/newaov" --hdr /nonexistent/x.hdr
unchanged "new --aov dir, bad --hdr"
# one AOV file that cannot be replaced (a directory in its place): no AOV and no image replaced
fresh_outputs
mkdir "$T/o/aov/normal.pfm"
expect_error "an AOV blocked" "normal\.pfm" -- "${R[@]}" "${ALL[@]}"
rmdir "$T/o/aov/normal.pfm"
unchanged "an AOV blocked"
# the disk fills up during the .pfm, simulated with a file size limit (no root needed; SIGXFSZ
# ignored, so write() fails with EFBIG): 100 KiB lets a 200x100 frame's PNGs (under 60 KiB) and
# .hdr (at most 78 KiB) through and stops its .pfm (234 KiB) partway.
fresh_outputs
(ulimit -f 100; trap '' XFSZ; exec "$SL" render scenes/default.json --size 200x100 -n 4 -q -o "$T/o/o.png" \
    --hdr "$T/o/o.hdr" --pfm "$T/o/o.pfm" --normals "$T/o/n.png") >"$T/out" 2>"$T/err"
status=$?
if [ $status -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -q 'o\.pfm.*write failed' "$T/err"; then
    ok "disk full during the .pfm: $(cat "$T/err")"
else
    fail "disk full during the .pfm: status $status, stderr: $(head -3 "$T/err" | tr '\n' ' ')"
fi
unchanged "disk full during the .pfm"
# and when everything succeeds, everything is replaced
fresh_outputs
if "${R[@]}" "${ALL[@]}" 2>"$T/err" && [ "$(head -c 4 "$T/o/o.png" | tail -c 3)" = PNG ] &&
    [ "$(head -c 2 "$T/o/o.pfm")" = PF ] && [ "$(head -c 2 "$T/o/aov/position.pfm")" = PF ] &&
    [ "$(head -c 4 "$T/o/n.png" | tail -c 3)" = PNG ] && [ "$(head -c 2 "$T/o/o.hdr")" = "#?" ] &&
    [ -z "$(cd "$T/o" && find . -name '*tmp*')" ]; then
    ok "a good render replaces every output, leaves no temporary"
else
    fail "a good render did not write every output: $(cat "$T/err")"
fi

# ---- symbolic links written through, non-regular targets refused ----
mkdir "$T/l"
echo old >"$T/l/real.png"
ln -s real.png "$T/l/link.png"
if "${R[@]}" -o "$T/l/link.png" && [ -L "$T/l/link.png" ] && [ "$(readlink "$T/l/link.png")" = real.png ] &&
    [ "$(head -c 4 "$T/l/real.png" | tail -c 3)" = PNG ] && [ "$(ls -A "$T/l" | wc -l)" -eq 2 ]; then
    ok "-o on a symbolic link writes its target, the link stays"
else
    fail "-o on a symbolic link: $(ls -lA "$T/l" | tr '\n' ' ')"
fi
ln -s sub/new.png "$T/l/dangling.png"
mkdir "$T/l/sub"
if "${R[@]}" -o "$T/l/dangling.png" && [ -L "$T/l/dangling.png" ] && [ -f "$T/l/sub/new.png" ]; then
    ok "-o on a link to a file not there yet creates the target"
else
    fail "-o on a dangling link: $(ls -lAR "$T/l" | tr '\n' ' ')"
fi
mkfifo "$T/l/fifo.png"
expect_error "-o on a FIFO" "fifo\.png.*(FIFO|not a regular file)" -- "${R[@]}" -o "$T/l/fifo.png"
[ -p "$T/l/fifo.png" ] && ok "the FIFO is still a FIFO" || fail "the FIFO was replaced"
ln -s /dev/null "$T/l/null.png"
expect_error "-o on a link to a device" "null\.png.*(device|not a regular file)" -- "${R[@]}" -o "$T/l/null.png"
[ -L "$T/l/null.png" ] && [ -c /dev/null ] && ok "the link to /dev/null is still a link" || fail "the link to /dev/null was replaced"
mkdir "$T/l/dir.png"
expect_error "-o on a directory" "dir\.png.*(directory|not a regular file)" -- "${R[@]}" -o "$T/l/dir.png"
if [ -z "$(find "$T/l" -name '*tmp*')" ]; then ok "no temporary left by the refusals"; else
    fail "temporaries left: $(find "$T/l" -name '*tmp*' | tr '\n' ' ')"; fi

# ---- temporaries of killed runs ----
mkdir "$T/k"
sh -c 'exit 0' & dead=$!
wait $dead
dd if=/dev/zero of="$T/k/.o.png.softlight-tmp.$dead" bs=1024 count=64 status=none
dd if=/dev/zero of="$T/k/.o.png.softlight-tmp.$$" bs=1024 count=1 status=none
dd if=/dev/zero of="$T/k/.other.png.softlight-tmp.$dead" bs=1024 count=1 status=none
"${R[@]}" -o "$T/k/o.png"
if [ ! -e "$T/k/.o.png.softlight-tmp.$dead" ]; then ok "a dead run's temporary of o.png was removed"; else
    fail "a dead run's temporary of o.png is still there"; fi
if [ -e "$T/k/.o.png.softlight-tmp.$$" ] && [ -e "$T/k/.other.png.softlight-tmp.$dead" ]; then
    ok "a live run's temporary, and another output's, were kept"
else
    fail "removed a temporary that was not a dead run's of o.png: $(ls -A "$T/k" | tr '\n' ' ')"
fi

echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
