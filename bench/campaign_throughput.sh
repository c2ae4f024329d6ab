#!/usr/bin/env bash
# Campaign throughput: runs per minute of `rfsitl sweep` on this machine for
# the six-UAV batch scenario (scenarios/six_uav_batch.yaml: six nodes, five
# 10 Hz flows and a broadcast), 10 virtual seconds per run, one engine thread
# per run, JOBS runs at once (default: one per core). Each repetition is a
# fresh campaign of RUNS runs (seeds 1..RUNS); prints each and the median.
#   bash bench/campaign_throughput.sh                 # release build, 3 x 12 runs
#   RUNS=24 REPEAT=5 JOBS=2 bash bench/campaign_throughput.sh
# BIN=path/to/rfsitl skips the build (e.g. to time another build).
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS="${RUNS:-12}"
REPEAT="${REPEAT:-3}"
JOBS="${JOBS:-$(nproc)}"
if [ -z "${BIN:-}" ]; then
  bash scripts/build.sh release rfsitl >/dev/null
  BIN=build/release/apps/rfsitl
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat >"$work/throughput.yaml" <<YAML
scenario: $PWD/scenarios/six_uav_batch.yaml
settings: {time.duration_s: 10}
seeds: $RUNS
YAML
rates=()
for i in $(seq "$REPEAT"); do
  rm -rf "$work/throughput.results"
  start=$(date +%s.%N)
  "$BIN" sweep "$work/throughput.yaml" --jobs "$JOBS" >/dev/null
  end=$(date +%s.%N)
  ok=$(grep -c ',ok,' "$work/throughput.results/results.csv" || true)
  [ "$ok" -eq "$RUNS" ] || { echo "campaign_throughput: only $ok of $RUNS runs ok" >&2; exit 1; }
  rate=$(echo "$RUNS * 60 / ($end - $start)" | bc -l)
  rates+=("$rate")
  printf 'campaign_throughput: repetition %d: %d runs in %.2f s: %.1f runs/min\n' \
    "$i" "$RUNS" "$(echo "$end - $start" | bc -l)" "$rate"
done
median=$(printf '%s\n' "${rates[@]}" | sort -g | awk '{v[NR]=$1} END {print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}')
printf 'campaign_throughput: six_uav_batch, 10 virtual s per run, %d jobs on %d cores: median %.1f runs/min\n' \
  "$JOBS" "$(nproc)" "$median"
