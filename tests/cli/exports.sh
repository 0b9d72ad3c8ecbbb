#!/usr/bin/env bash
# exports.sh BUILD_DIR - the shared library exports only softlight's public functions: every
# defined dynamic symbol starts with sl_ (the SL_API ones; the rest is built with hidden
# visibility); every global the static library defines carries the sl_ prefix too, so linking
# it never takes a name from its user; the SONAME carries the major version of
# include/softlight/version.h; and the libraries hold no absolute path of the source tree
# outside their debug information.
set -euo pipefail
BUILD=${1:?usage: $0 BUILD_DIR}
lib=$BUILD/libsoftlight.so
# Symbols the toolchain may define in any shared object.
allowed='^(_init|_fini|_edata|_end|__bss_start)$'
fails=0
syms=$(nm -D --defined-only "$lib" | awk '{print $3}')
count=$(printf '%s\n' "$syms" | grep -c '^sl_' || true)
others=$(printf '%s\n' "$syms" | grep -v '^sl_' | grep -Ev "$allowed" || true)
if [ -n "$others" ]; then
    echo "FAIL exported symbols without the sl_ prefix:"; printf '  %s\n' $others; fails=1
fi
if [ "$count" -lt 1 ]; then echo "FAIL no sl_ symbol exported"; fails=1; else echo "ok   $count sl_ symbols exported, nothing else"; fi
# An internal function of the library stays hidden.
if printf '%s\n' "$syms" | grep -x sl_scene_load_model_alone >/dev/null; then echo "FAIL internal symbols exported"; fails=1; fi
# The static library's globals, internals included: names the compiler or a sanitizer generates
# (a leading double underscore) are the only others.
static_bad=$(nm -g --defined-only "$BUILD/libsoftlight.a" | awk 'NF == 3 { print $3 }' | grep -v -e '^sl_' -e '^__' | sort -u || true)
if [ -n "$static_bad" ]; then
    echo "FAIL globals of libsoftlight.a without the sl_ prefix:"; printf '  %s\n' $static_bad; fails=1
else
    echo "ok   every global of libsoftlight.a carries the sl_ prefix"
fi
major=$(sed -n 's/^#define SL_VERSION_MAJOR \([0-9]*\)/\1/p' include/softlight/version.h)
soname=$(readelf -d "$lib" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
if [ "$soname" = "libsoftlight.so.$major" ]; then echo "ok   SONAME $soname"; else echo "FAIL SONAME '$soname'"; fails=1; fi
# Debug information names the sources by design: it is stripped from copies first. The
# sanitizers record each object's source path in its data, so a sanitized build is not checked.
if grep -q '^SL_SANITIZE:BOOL=ON' "$BUILD/CMakeCache.txt"; then
    echo "skip source tree paths: a sanitized build"
else
    T=$(mktemp -d "${TMPDIR:-/tmp}/softlight-exports.XXXXXX")
    trap 'rm -rf "$T"' EXIT
    objcopy --strip-debug "$BUILD/libsoftlight.a" "$T/libsoftlight.a"
    objcopy --strip-debug "$lib" "$T/libsoftlight.so"
    if strings "$T/libsoftlight.a" "$T/libsoftlight.so" | grep -F "$PWD" >/dev/null; then
        echo "FAIL the libraries hold the source tree's path $PWD"; fails=1
    else
        echo "ok   no source tree path in the libraries"
    fi
fi
exit $fails
