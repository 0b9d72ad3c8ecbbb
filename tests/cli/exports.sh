#!/usr/bin/env bash
# exports.sh BUILD - every global symbol the library defines carries the sl_ prefix, so that
# linking libsoftlight never takes a name from its user. Allowed: names the compiler or a
# sanitizer generates (a leading double underscore). Lists each offender; exit 1 if any.
set -euo pipefail
lib=$1/libsoftlight.a
[ -f "$lib" ] || { echo "no $lib"; exit 1; }
bad=$(nm -g --defined-only "$lib" | awk 'NF == 3 { print $3 }' | grep -v -e '^sl_' -e '^__' | sort -u || true)
if [ -n "$bad" ]; then
  echo "globals of $lib without the sl_ prefix:"
  echo "$bad"
  exit 1
fi
