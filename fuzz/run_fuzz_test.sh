#!/usr/bin/env bash
# Runs one fuzz target for SECONDS: run_fuzz_test.sh BINARY SECONDS WORKDIR SEED_DIR...
# New inputs go to WORKDIR/corpus (emptied first); a crash input to WORKDIR/crash-*, and the exit
# status is then non-zero. Used by ctest (fuzz/CMakeLists.txt) and scripts/fuzz.
set -euo pipefail
binary=$1 seconds=$2 work=$3
shift 3
rm -rf "$work"
mkdir -p "$work/corpus"
# -rss_limit_mb: a reader that allocates what a hostile header claims is a bug, not a slow input.
# -timeout: one input taking 10 s is a hang.
if ! "$binary" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$work/" "$work/corpus" "$@" >"$work/log" 2>&1; then
  tail -n 60 "$work/log" >&2
  echo "fuzz: $(basename "$binary") failed; the input is in $work/ (copy it to" \
    "tests/robustness/corpus/fuzz_NAME.EXT and fix the reader)" >&2
  exit 1
fi
grep -E '^stat::number_of_executed_units|^Done' "$work/log" || true
