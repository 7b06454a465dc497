#!/usr/bin/env bash
# make fuzz-smoke's runner: every BUILD_DIR/bin/*_fuzzer for SECONDS from its seeds (tests/fuzz/seeds/NAME)
# and its dictionary (tests/fuzz/NAME.dict), JOBS of them at a time (each on its own core: a fuzzer is one
# process), then one line per fuzzer in name order; a finding prints its log's tail and fails.
#
#   run_smoke.sh BUILD_DIR SECONDS TIMEOUT JOBS
set -uo pipefail
build=$1 seconds=$2 timeout=$3 jobs=$4
shopt -s nullglob
fuzzers=("$build"/bin/*_fuzzer)
if [ ${#fuzzers[@]} -eq 0 ]; then echo "fuzz-smoke: no fuzzer in $build/bin" >&2; exit 1; fi
mkdir -p "$build/logs" "$build/artifacts"

run_one() {
  local fuzzer=$1 name seeds dict_flag=()
  name=$(basename "$fuzzer")
  mkdir -p "$build/corpus/$name"
  seeds=tests/fuzz/seeds/${name%_fuzzer}
  [ -d "$seeds" ] || seeds=
  [ -f "tests/fuzz/${name%_fuzzer}.dict" ] && dict_flag=("-dict=tests/fuzz/${name%_fuzzer}.dict")
  "$fuzzer" -max_total_time="$seconds" -timeout="$timeout" -max_len=65536 -rss_limit_mb=2048 -print_final_stats=1 \
    "${dict_flag[@]}" -artifact_prefix="$build/artifacts/$name-" "$build/corpus/$name" $seeds > "$build/logs/$name.log" 2>&1
  echo $? > "$build/logs/$name.status"
}

running=0
for fuzzer in "${fuzzers[@]}"; do
  run_one "$fuzzer" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait

failed=""
for fuzzer in "${fuzzers[@]}"; do
  name=$(basename "$fuzzer")
  log=$build/logs/$name.log
  status=$(cat "$build/logs/$name.status" 2>/dev/null || echo "none")
  if [ "$status" = 0 ]; then
    echo "== $name: $seconds s, $(sed -n 's/^stat::number_of_executed_units: *//p' "$log") inputs, no finding"
  else
    echo "== $name: FAILED (exit $status), log $log:"
    tail -n 40 "$log"
    failed="$failed $name"
  fi
done
if [ -n "$failed" ]; then echo "fuzz-smoke: findings in:$failed" >&2; exit 1; fi
