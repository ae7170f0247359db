#!/usr/bin/env bash
# Runs one libFuzzer target for SECONDS on a copy of its seed corpus.
# Usage: run_fuzz.sh FUZZ_BINARY SEED_CORPUS_DIR SECONDS [ARTIFACT_DIR]
# Exit 77 (ctest: skipped) when the binary has not been built (`./run fuzz` builds it with clang).
# Limits: 1024 MB RSS per process (-rss_limit_mb; -malloc_limit_mb likewise), 10 s per input.
# Prints libFuzzer's last status line and the counts of crash-/timeout-/oom- artifacts.
set -uo pipefail
bin=$1 seed=$2 seconds=$3 art=${4:-}
if [ ! -x "$bin" ]; then
  echo "skipped: $bin not built (./run fuzz builds the libFuzzer targets with clang)"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
art=${art:-$work/artifacts}
mkdir -p "$work/corpus" "$art"
log="$work/log"
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1} \
UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
  "$bin" -max_total_time="$seconds" -rss_limit_mb=1024 -malloc_limit_mb=1024 -timeout=10 \
  -artifact_prefix="$art/" -print_final_stats=1 "$work/corpus" "$seed" >"$log" 2>&1
rc=$?
name=$(basename "$bin")
crashes=$(find "$art" -name 'crash-*' | wc -l)
timeouts=$(find "$art" -name 'timeout-*' | wc -l)
ooms=$(find "$art" -name 'oom-*' | wc -l)
runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
echo "$name: ${seconds} s, $runs runs, crashes $crashes, timeouts $timeouts, over memory $ooms, exit $rc"
if [ $rc -ne 0 ]; then
  tail -40 "$log"
  exit 1
fi
exit 0
