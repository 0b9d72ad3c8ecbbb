#!/usr/bin/env bash
# fuzz.sh BUILD_DIR SECONDS [SEED] - run every libFuzzer target for a bounded time on its seed corpus.
# A crash, hang (-timeout), leak or out-of-memory fails the run; the reproducer is left in
# fuzz/artifacts/. The seed corpus is copied so the committed one never grows.
# The random seed is fixed (1 unless given), so a run explores a prefix of one sequence of inputs:
# CI's short run finds nothing a longer local run with the same seed has not already been through,
# and a failure it reports can be replayed. Give another seed (or 0: libFuzzer picks) to explore.
#
# Seeds: fuzz/corpus/<target>/ for each target (a target without one fails the run: starting
# from nothing, a short run never gets past the format's first checks). fuzz_texture's holds valid
# small PNGs and JPEGs of every layout (valid_*: grey 1..16 bits, grey + alpha, RGB, RGBA,
# palette, colour keys, Adam7 interlacing; baseline 4:2:0 / 4:2:2 / 4:4:4, restart markers,
# progressive, CMYK and YCCK; written by fuzz/make_image_seeds.c), so mutations start deep in the
# decoders, beside hand-made corrupt files and reproducers of past findings.
#
# `make test` runs each target for FUZZ_SECONDS (15) s: a smoke test. A real campaign runs one
# target for hours with a fresh random seed and keeps what it learns:
#   make fuzz FUZZ_SECONDS=0                      # just builds build-fuzz (clang, ASan + UBSan)
#   FUZZ_TARGETS=fuzz_texture FUZZ_KEEP=out/fuzz-corpus bash scripts/fuzz.sh build-fuzz 14400 0
# FUZZ_TARGETS: the targets to run (space-separated names; default all). FUZZ_KEEP=DIR: the run
# starts from DIR/<target> as well as the seeds, and the corpus it grew is merged back there
# (-merge=1: only inputs that add coverage), so the next run resumes; DIR is never committed
# (copy a small input that reaches new code into fuzz/corpus/ by hand, under 4 KB).
set -euo pipefail
build=$1; seconds=${2:-20}; seed=${3:-1}
status=0
# assimp's own leaks (fuzz_model) are not softlight's to fix: scripts/lsan-assimp.supp says why.
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$PWD/scripts/lsan-assimp.supp"
[ "$seconds" -gt 0 ] || exit 0
# Targets run side by side, FUZZ_JOBS at a time (default: one per core): each is one process on
# one core, and a target's report is printed whole when it ends.
jobs_max=${FUZZ_JOBS:-$(nproc)}

# fuzz_one NAME BIN: one target's run; its report on stdout, exit status 1 when it failed.
fuzz_one() {
  local name=$1 bin=$2 corpus keep=""
  corpus=$(mktemp -d)
  cp -r "fuzz/corpus/$name/." "$corpus/"
  if [ -n "${FUZZ_KEEP:-}" ]; then
    keep="$FUZZ_KEEP/$name"; mkdir -p "$keep"
    cp -r "$keep/." "$corpus/"
  fi
  local failed=0
  echo "fuzz: $name for ${seconds}s"
  if ! "$bin" -seed="$seed" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -max_len=65536 \
       -artifact_prefix=fuzz/artifacts/"$name"- -print_final_stats=0 "$corpus" >"$corpus.log" 2>&1; then
    echo "fuzz: $name FAILED"; tail -40 "$corpus.log"; failed=1
  else
    grep -E '^#[0-9]+.*DONE|Done [0-9]+ runs' "$corpus.log" | tail -1 || true
  fi
  if [ -n "$keep" ]; then
    "$bin" -merge=1 "$keep" "$corpus" >/dev/null 2>&1 || echo "fuzz: $name: merging into $keep failed"
  fi
  rm -rf "$corpus" "$corpus.log"
  return $failed
}

mkdir -p fuzz/artifacts
reports=$(mktemp -d)
trap 'rm -rf "$reports"' EXIT
running=0
for bin in "$build"/fuzz_*; do
  [ -x "$bin" ] || continue
  name=$(basename "$bin")
  if [ -n "${FUZZ_TARGETS:-}" ] && ! [[ " $FUZZ_TARGETS " == *" $name "* ]]; then continue; fi
  if ! [ -d "fuzz/corpus/$name" ] || [ -z "$(ls -A "fuzz/corpus/$name")" ]; then
    echo "fuzz: $name has no seed corpus (fuzz/corpus/$name)"; status=1; continue
  fi
  if [ "$running" -ge "$jobs_max" ]; then
    wait -n || status=1
    running=$((running - 1))
  fi
  ( rc=0; fuzz_one "$name" "$bin" >"$reports/$name" 2>&1 || rc=$?; cat "$reports/$name"; exit $rc ) &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || status=1
  running=$((running - 1))
done
exit $status
