#!/usr/bin/env bash
# The lab sheet's outputs are what the tools print now (docs/TEACHING.md, docs/teaching/): runs
# scripts/make-teaching-figures --check PART into WORK and compares every file it made with the
# committed one (scripts/teaching-sheet --compare: byte for byte, timings aside). The bunny part
# is skipped (exit 77, CTest's SKIP_RETURN_CODE) when meshes/fetch has not fetched the bunny, as
# the other tests that use it do.
# Usage: tests/docs/teaching_outputs.sh small|bunny OCTRACE WORK
set -euo pipefail
part="$1" octrace="$2" work="$3"
cd "$(dirname "$0")/../.."
if [[ "$part" == bunny && ! -f meshes/cache/bunny.obj ]]; then
  echo "teaching_outputs: skipped: meshes/cache/bunny.obj missing (meshes/fetch bunny)"
  exit 77
fi
rm -rf "$work"
OCTRACE="$octrace" scripts/make-teaching-figures --check "$part" "$work"
scripts/teaching-sheet --compare docs/teaching "$work"
