#!/usr/bin/env bash
# The fuzz smoke for CI: builds every target (release, AddressSanitizer)
# and runs each for a short, fixed number of executions from the committed
# and generated seeds, with its dictionary and the memory limits of
# targets.sh; then runs each once on the real-sized seeds (the committed
# session cut to two seconds, the default avatar). Fails on any crash,
# panic, hang (-timeout) or out-of-memory. The last line is
#   test result: ok. N passed; 0 failed (fuzz smoke: ...)
#
#   tests/fuzz/smoke.sh            # SMOKE_RUNS=5000 per target (fewer for two)
#   SMOKE_RUNS=20000 tests/fuzz/smoke.sh
set -uo pipefail
source "$(dirname "$0")/targets.sh"
# Executions per target; the two slow targets (a folder written per input,
# a capture driven through hundreds of calls) run a fifth and a twentieth.
SMOKE_RUNS="${SMOKE_RUNS:-5000}"
runs_for() {
  case "$1" in
    folder_import) echo $((SMOKE_RUNS / 5)) ;;
    capture_ffi) echo $((SMOKE_RUNS / 20)) ;;
    *) echo "$SMOKE_RUNS" ;;
  esac
}

start=$SECONDS
ensure_cargo_fuzz || exit 1
build_targets || exit 1
built=$SECONDS
WORK="$FUZZ_DIR/corpus/smoke"
LOGS="$FUZZ_DIR/logs/smoke"
rm -rf "$WORK" "$LOGS"
mkdir -p "$WORK" "$LOGS"
make_seeds "$WORK/seeds" --large || exit 1

passed=0
failed=0
failures=()
total_runs=0
for spec in "${TARGET_SPECS[@]}"; do
  IFS=: read -r name dict max_len <<<"$spec"
  runs=$(runs_for "$name")
  corpus="$WORK/$name"
  artifacts="$WORK/artifacts/$name/"
  mkdir -p "$corpus" "$artifacts"
  seeds=("$WORK/seeds/$name")
  [ -d "$FUZZ_DIR/seeds/$name" ] && seeds+=("$FUZZ_DIR/seeds/$name")
  log="$LOGS/$name.log"
  t0=$SECONDS
  ok=1
  "$BIN/$name" "$corpus" "${seeds[@]}" -runs="$runs" \
    -dict="$FUZZ_DIR/dict/$dict.dict" -max_len="$max_len" \
    -rss_limit_mb="$RSS_LIMIT_MB" -malloc_limit_mb="$MALLOC_LIMIT_MB" \
    -timeout="$TIMEOUT_S" -print_final_stats=1 -artifact_prefix="$artifacts" \
    >"$log" 2>&1 || ok=0
  large="$WORK/seeds/large/$name"
  if [ "$ok" = 1 ] && [ -d "$large" ]; then
    "$BIN/$name" -rss_limit_mb="$RSS_LIMIT_MB" -malloc_limit_mb="$MALLOC_LIMIT_MB" \
      -timeout="$TIMEOUT_S" -artifact_prefix="$artifacts" "$large"/* \
      >"$LOGS/$name.large.log" 2>&1 || ok=0
  fi
  executed=$(final_stat "$log" number_of_executed_units)
  total_runs=$((total_runs + executed))
  if [ "$ok" = 1 ]; then
    passed=$((passed + 1))
    echo "fuzz smoke: $name ok, $executed runs in $((SECONDS - t0)) s, peak RSS $(final_stat "$log" peak_rss_mb) MB"
  else
    failed=$((failed + 1))
    failures+=("$name")
    echo "fuzz smoke: $name FAILED (log: $log; input: $artifacts)"
    grep -E "ERROR|panicked|SUMMARY" "$log" "$LOGS/$name.large.log" 2>/dev/null | head -5
  fi
done
clean_scratch

summary="build $((built - start)) s, runs $((SECONDS - built)) s, $total_runs executions"
if [ "$failed" = 0 ]; then
  echo "test result: ok. $passed passed; 0 failed (fuzz smoke: $summary)"
else
  echo "test result: FAILED. $passed passed; $failed failed (fuzz smoke: ${failures[*]}; $summary)"
  exit 1
fi
