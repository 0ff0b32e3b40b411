#!/usr/bin/env bash
# The long fuzzing campaign: every target (or those named) for RUNS
# executions each (default 1,000,000), at nice 10, JOBS targets at a time
# (default 1), each target's RUNS split over WORKERS processes that share
# its corpus (default 1; for a slow target on a machine with cores to
# spare). Logs in logs/campaign/TARGET.log (TARGET.wK.log per worker),
# crashes in artifacts/TARGET/, the summary table in
# logs/campaign/summary.md (executions and exec/s summed over workers,
# peak RSS the largest).
#
#   tests/fuzz/campaign.sh [RUNS] [TARGET...]
#   JOBS=2 tests/fuzz/campaign.sh 1000000
#   WORKERS=2 tests/fuzz/campaign.sh 1000000 capture_ffi
set -euo pipefail
source "$(dirname "$0")/targets.sh"
RUNS="${1:-1000000}"
shift || true
JOBS="${JOBS:-1}"
WORKERS="${WORKERS:-1}"
LOGS="$FUZZ_DIR/logs/campaign"
mkdir -p "$LOGS"

ensure_cargo_fuzz
build_targets
make_seeds "$FUZZ_DIR/corpus/generated"

# Runs one target, its runs split over WORKERS processes; its corpus grows
# in corpus/TARGET (seeded from the committed and generated seeds).
run_target() {
  local name="$1" dict="$2" max_len="$3"
  local corpus="$FUZZ_DIR/corpus/$name" artifacts="$FUZZ_DIR/artifacts/$name/"
  mkdir -p "$corpus" "$artifacts"
  local seeds=("$FUZZ_DIR/corpus/generated/$name")
  [ -d "$FUZZ_DIR/seeds/$name" ] && seeds+=("$FUZZ_DIR/seeds/$name")
  local start=$SECONDS worker rc=0
  rm -f "$LOGS/$name".log "$LOGS/$name".w*.log
  for ((worker = 1; worker <= WORKERS; worker++)); do
    local log="$LOGS/$name.log"
    [ "$WORKERS" -gt 1 ] && log="$LOGS/$name.w$worker.log"
    # The first worker's remainder keeps the total exactly RUNS.
    local runs=$((RUNS / WORKERS))
    [ "$worker" -eq 1 ] && runs=$((runs + RUNS % WORKERS))
    nice -n 10 "$BIN/$name" "$corpus" "${seeds[@]}" \
      -runs="$runs" -dict="$FUZZ_DIR/dict/$dict.dict" -max_len="$max_len" \
      -rss_limit_mb="$RSS_LIMIT_MB" -malloc_limit_mb="$MALLOC_LIMIT_MB" \
      -timeout="$TIMEOUT_S" -print_final_stats=1 -artifact_prefix="$artifacts" \
      >"$log" 2>&1 &
  done
  for ((worker = 1; worker <= WORKERS; worker++)); do
    wait -n || rc=$?
  done
  echo "$rc" >"$LOGS/$name.rc"
  echo $((SECONDS - start)) >"$LOGS/$name.seconds"
}

running=0
for spec in "${TARGET_SPECS[@]}"; do
  IFS=: read -r name dict max_len <<<"$spec"
  if [ $# -gt 0 ] && [[ ! " $* " == *" $name "* ]]; then continue; fi
  echo "campaign: $name, $RUNS runs (log: $LOGS/$name.log)"
  run_target "$name" "$dict" "$max_len" &
  running=$((running + 1))
  if [ "$running" -ge "$JOBS" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true
clean_scratch

# The summary: one row per target run.
summary="$LOGS/summary.md"
{
  echo "Campaign of $(date -u '+%Y-%m-%d %H:%M UTC'), $RUNS runs per target, nice 10, JOBS=$JOBS, WORKERS=$WORKERS."
  echo "Limits: -rss_limit_mb=$RSS_LIMIT_MB -malloc_limit_mb=$MALLOC_LIMIT_MB -timeout=$TIMEOUT_S."
  echo
  echo "| target | executions | exec/s | peak RSS (MB) | wall time (s) | crashes | exit |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  for spec in "${TARGET_SPECS[@]}"; do
    IFS=: read -r name _ _ <<<"$spec"
    logs=()
    for log in "$LOGS/$name".log "$LOGS/$name".w*.log; do
      [ -f "$log" ] && logs+=("$log")
    done
    [ "${#logs[@]}" -gt 0 ] || continue
    crashes=$(find "$FUZZ_DIR/artifacts/$name" -type f 2>/dev/null \
      \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' -o -name 'leak-*' \) | wc -l)
    seconds=$(cat "$LOGS/$name.seconds" 2>/dev/null || echo -)
    rc=$(cat "$LOGS/$name.rc" 2>/dev/null || echo -)
    executions=0 per_second=0 rss=0
    for log in "${logs[@]}"; do
      executions=$((executions + $(final_stat "$log" number_of_executed_units)))
      per_second=$((per_second + $(final_stat "$log" average_exec_per_sec)))
      peak=$(final_stat "$log" peak_rss_mb)
      [ "$peak" -gt "$rss" ] && rss=$peak
    done
    echo "| $name | $executions | $per_second | $rss | $seconds | $crashes | $rc |"
  done
} >"$summary"
cat "$summary"
