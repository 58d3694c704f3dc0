#!/usr/bin/env bash
# Runs one fuzz target for SECONDS: run_fuzz_test.sh PROGRAM TARGET SECONDS WORKDIR
# PROGRAM is flatmorph_fuzz, TARGET one of its readers (fuzz/README.md), seeded from the test
# fixtures of its format (read only). New inputs go to
# WORKDIR/corpus (emptied first); a crash input to WORKDIR/crash-*, and the exit status is then
# non-zero. Used by ctest (fuzz/CMakeLists.txt) and scripts/fuzz.
set -euo pipefail
program=$1 target=$2 seconds=$3 work=$4
root=$(cd "$(dirname "$0")/.." && pwd)
case "$target" in
  fuzz_material | fuzz_printer | fuzz_csv) seeds=(profiles/materials profiles/printers tests/robustness/corpus) ;;
  fuzz_stack) seeds=(tests/data/stack) ;;
  fuzz_gcode) seeds=(tests/data/gcode/unsafe) ;;
  fuzz_height_image) seeds=(tests/data/image) ;;
  fuzz_dxf_outlines | fuzz_svg_outlines) seeds=(tests/data/tiles) ;;
  fuzz_crease_pattern_svg) seeds=(tests/data/origami tests/data/tiles) ;;
  fuzz_obj | fuzz_ply | fuzz_stl | fuzz_off) seeds=(tests/data/mesh tests/robustness/corpus) ;;
  *) echo "run_fuzz_test.sh: unknown target $target (fuzz/README.md lists them)" >&2; exit 2 ;;
esac
rm -rf "$work"
mkdir -p "$work/corpus"
# -rss_limit_mb: a reader that allocates what a hostile header claims is a bug, not a slow input.
# -timeout: one input taking 10 s is a hang.
if ! FLATMORPH_FUZZ_TARGET=$target "$program" -max_total_time="$seconds" -max_len=65536 \
    -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 -artifact_prefix="$work/" \
    "$work/corpus" "${seeds[@]/#/$root/}" >"$work/log" 2>&1; then
  tail -n 60 "$work/log" >&2
  echo "fuzz: $target failed; the input is in $work/ (copy it to" \
    "tests/robustness/corpus/fuzz_NAME.EXT and fix the reader; replay it with" \
    "FLATMORPH_FUZZ_TARGET=$target $program FILE)" >&2
  exit 1
fi
grep -E '^stat::number_of_executed_units|^Done' "$work/log" || true
