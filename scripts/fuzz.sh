#!/usr/bin/env bash
# Runs every libFuzzer target for a while and prints one line of figures per target.
#   scripts/fuzz.sh BUILD_DIR [SECONDS_PER_TARGET] [TARGET...]
# BUILD_DIR must be a GT_FUZZ build (the asan preset: clang, ASan + UBSan, libFuzzer), which
# `make fuzz` prepares. The corpus starts from the generated seeds and regression cases
# (tests/fuzz/make_corpus.cpp) and grows in BUILD_DIR/fuzz-work/TARGET, kept between runs;
# crashes, timeouts and out-of-memory inputs land in BUILD_DIR/fuzz-findings/TARGET/, and the
# script exits non-zero when any target found one. FUZZ_JOBS targets run at once (default 1).
set -euo pipefail

build=${1:?usage: scripts/fuzz.sh BUILD_DIR [SECONDS_PER_TARGET] [TARGET...]}
seconds=${2:-60}
shift $(($# < 2 ? $# : 2))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(gltf radiance point_set_cache gaze_trace calibration datagram)
fi
jobs=${FUZZ_JOBS:-1}

if [ ! -x "$build/gazetrace_fuzz_corpus" ]; then
  echo "fuzz: $build has no gazetrace_fuzz_corpus; build the asan preset first (make fuzz)" >&2
  exit 1
fi
"$build/gazetrace_fuzz_corpus" "$build/fuzz-corpus" >/dev/null

# Leaks are real findings here (no Vulkan driver in these programs).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

run_one() {
  local t=$1
  local exe="$build/gazetrace_fuzz_$t"
  local work="$build/fuzz-work/$t" findings="$build/fuzz-findings/$t"
  local log="$build/fuzz-findings/$t.log"
  mkdir -p "$work" "$findings"
  # -timeout: one input may take 10 s (a hang is a finding); -rss_limit_mb: 2 GB per input;
  # -max_len: mutations stay small (the large regression cases are replayed whole by CTest).
  set +e
  "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
    -print_final_stats=1 \
    -artifact_prefix="$findings/" "$work" "$build/fuzz-corpus/$t/seeds" \
    "$build/fuzz-corpus/$t/regressions" >"$log" 2>&1
  local rc=$?
  set -e
  local execs cov ft corpus found
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  corpus=$(find "$work" -type f | wc -l)
  found=$(find "$findings" -type f | wc -l)
  printf '%-16s %6ss %12s execs %6s edges %7s features %6s corpus %3s findings  rc %s\n' \
    "$t" "$seconds" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$corpus" "$found" "$rc"
  [ "$rc" -eq 0 ] && [ "$found" -eq 0 ]
}

status=0
pids=()
for t in "${targets[@]}"; do
  run_one "$t" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do
  wait "$p" || status=1
done
if [ $status -ne 0 ]; then
  echo "fuzz: findings in $build/fuzz-findings (logs: $build/fuzz-findings/TARGET.log)" >&2
fi
exit $status
