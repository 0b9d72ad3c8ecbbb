#!/usr/bin/env bash
# sweep_sharded_truth.sh BUILD_DIR - the speed-vs-error sweep reading a ground truth made by sharded
# `softlight truth --parts` runs (GNU parallel, merged): every error figure of the sweep equals the
# one it gets computing the truth itself (the CSV without its timing columns), the jobs list names
# what to run, and a truth that is not this run's (another scene's, or another environment
# intensity's: the spot check integrates pixels again) is refused with one line, exit 2.
# A sanitized suite skips it: its 203 variants take two minutes there, and the truth's shards and
# merge run under the sanitizers in shard.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
B="$(cd "$1" && pwd)"
if grep -q '^SL_SANITIZE:BOOL=ON' "$B/CMakeCache.txt"; then
    echo "skip: a sanitized suite (shard.sh runs the sharded truth and its merge there)"
    exit 0
fi
command -v parallel >/dev/null || { echo "FAIL: GNU parallel missing (scripts/setup.sh installs it)"; exit 1; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
sweep=("$B/bench_speed_vs_error" --size 16x9 --scenes default --frames 1 --anchor-frames 0 --doc none --gl none)

jobs=$("${sweep[@]}" --truth-jobs)
[ "$jobs" = "default scenes/default.json 16 9" ] || fail "--truth-jobs printed '$jobs'"

OMP_WAIT_POLICY=passive "${sweep[@]}" --out "$T/own" --cache "$T/cache" 2>/dev/null
mkdir -p "$T/truth" "$T/other" "$T/dim"
parallel "$B/softlight" truth scenes/default.json --size 16x9 --parts "$T/truth/default-16x9" --threads 1 \
  --shard {}/3 ::: 1 2 3 >/dev/null 2>&1
"$B/softlight" merge -q "$T"/truth/default-16x9.shard-*-of-3
OMP_WAIT_POLICY=passive "${sweep[@]}" --out "$T/read" --truth "$T/truth" 2>/dev/null
python3 - "$T/own/speed-vs-error.csv" "$T/read/speed-vs-error.csv" <<'PY' || fail "the sweep's errors differ"
import csv, sys
def rows(path):  # every column but the timings
    return [{k: v for k, v in r.items() if not k.endswith('_ms')} for r in csv.DictReader(open(path))]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
if not a or a != b:
    diff = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), None)
    sys.exit(f"{len(a)} vs {len(b)} rows; first differing row {diff}")
print(f"sweep_sharded_truth: {len(a)} rows, errors identical")
PY

# not this run's truth: another scene's (coverage differs), another intensity's (spot check)
"$B/softlight" truth scenes/bunny.json --size 16x9 --parts "$T/other/default-16x9" >/dev/null 2>&1
if out=$("${sweep[@]}" --out "$T/x" --truth "$T/other" 2>&1); then fail "another scene's truth was accepted"; fi
[ "$(printf '%s\n' "$out" | grep -c 'mask.pfm differs from this run.s coverage')" = 1 ] || fail "message: $out"
ln -s "$PWD/scenes/envmaps" "$T/envmaps" # the scene's paths are relative to its file
sed 's/"intensity": *[0-9.]*/"intensity": 0.5/' scenes/default.json > "$T/dim.json"
grep -q '"intensity": 0.5' "$T/dim.json" || fail "scenes/default.json has no environment intensity to change"
"$B/softlight" truth "$T/dim.json" --size 16x9 --parts "$T/dim/default-16x9" >/dev/null 2>&1
if out=$("${sweep[@]}" --out "$T/y" --truth "$T/dim" 2>&1); then fail "another intensity's truth was accepted"; fi
printf '%s\n' "$out" | grep "is not this run's ground truth" >/dev/null || fail "message: $out"
echo "sweep_sharded_truth: ok"
