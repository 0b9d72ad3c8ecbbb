#!/usr/bin/env bash
# fuzz.sh BUILD_DIR SECONDS [SEED] - run every libFuzzer target for a bounded time on its seed corpus.
# A crash, hang (-timeout), leak or out-of-memory fails the run; the reproducer is left in
# fuzz/artifacts/. The seed corpus is copied so the committed one never grows.
# The random seed is fixed (1 unless given), so a run explores a prefix of one sequence of inputs:
# CI's short run finds nothing a longer local run with the same seed has not already been through,
# and a failure it reports can be replayed. Give another seed (or 0: libFuzzer picks) to explore.
set -euo pipefail
build=$1; seconds=${2:-20}; seed=${3:-1}
status=0
# assimp's own leaks (fuzz_model) are not softlight's to fix: scripts/lsan-assimp.supp says why.
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$PWD/scripts/lsan-assimp.supp"
for bin in "$build"/fuzz_*; do
  [ -x "$bin" ] || continue
  name=$(basename "$bin")
  corpus=$(mktemp -d)
  [ -d "fuzz/corpus/$name" ] && cp -r "fuzz/corpus/$name/." "$corpus/"
  mkdir -p fuzz/artifacts
  echo "fuzz: $name for ${seconds}s"
  if ! "$bin" -seed="$seed" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -max_len=65536 \
       -artifact_prefix=fuzz/artifacts/"$name"- -print_final_stats=0 "$corpus" >"$corpus.log" 2>&1; then
    echo "fuzz: $name FAILED"; tail -40 "$corpus.log"; status=1
  else
    grep -E '^#[0-9]+.*DONE|Done [0-9]+ runs' "$corpus.log" | tail -1 || true
  fi
  rm -rf "$corpus" "$corpus.log"
done
exit $status
