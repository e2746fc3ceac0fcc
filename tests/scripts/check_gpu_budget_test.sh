#!/usr/bin/env bash
# scripts/check-gpu-budget on saved ptxas reports (tests/data/ptxas/): the kernels as they were
# before the per-level traversal state (72 to 96 registers, 192 to 5,808 bytes of stack) are
# refused, each named with its figures; the kernels as they are now pass; a report with no
# kernel cannot be checked. No nvcc needed: GpuBudget.EveryKernelFitsOnHopper compiles.
# Usage: check_gpu_budget_test.sh SCRIPT DATA_DIR
set -u
script=$1 data=$2
failures=0
check() {  # what, expected status, file, then patterns the output must hold
  local what=$1 want=$2 file=$3
  shift 3
  local out status
  out=$("$script" --parse "$file" 2>&1)
  status=$?
  if [[ $status != "$want" ]]; then
    echo "FAIL $what: exit $status, wanted $want"
    echo "$out"
    failures=$((failures + 1))
  fi
  for p in "$@"; do
    if ! grep -qF -- "$p" <<<"$out"; then
      echo "FAIL $what: output lacks: $p"
      echo "$out"
      failures=$((failures + 1))
    fi
  done
}
check "before" 1 "$data/before-per-level-state.txt" \
  "renderKernel<CompactOctreeView> uses 96 registers and 5808 bytes of stack a thread" \
  "traceKernel<LinearOctreeView> uses 72 registers and 2800 bytes" \
  "renderKernel<ExhaustiveView> uses 80 registers and 192 bytes"
check "now" 0 "$data/per-level-state.txt" "renderKernel<LinearOctreeView>" "ok"
empty=$(mktemp)
echo "ptxas info    : 0 bytes gmem" >"$empty"
check "no kernel" 2 "$empty" "no kernel compiled for sm_90"
rm -f "$empty"
if [[ $failures != 0 ]]; then exit 1; fi
echo "check-gpu-budget: refuses, passes and cannot-check as it should"
