#!/usr/bin/env bash
# Whether the engine's self-tuned workers hold: rfsitl_virtual_speed at N = 6,
# 15, 64 and 128 with the default (tuned), 1 and 2 threads, RUNS runs of each
# interleaved, on this machine as it is ("as-is": whatever else runs) and again beside `stress-ng --cpu 2`
# (another job using both cores). Prints the median speed of each and the
# default's ratio to one thread's, with the CPU's steal time over each
# condition (/proc/stat: what a hypervisor took).
#
#   bash bench/thread_tuning.sh                 # needs build/release (scripts/build.sh release)
#   RUNS=5 LOAD=0 bash bench/thread_tuning.sh   # more runs; no stress-ng condition
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${BIN:-build/release/bench/rfsitl_virtual_speed}"
RUNS="${RUNS:-3}"
LOAD="${LOAD:-1}"
# nodes:duration, each run a second or more of wall time on 2 cores
CASES="${CASES:-6:120 15:60 64:10 128:5}"
[ -x "$BIN" ] || { echo "thread_tuning: $BIN is missing (bash scripts/build.sh release)" >&2; exit 2; }

# steal and total jiffies of the whole CPU so far
cpu_jiffies() { awk '/^cpu /{t=0; for (i=2;i<=NF;i++) t+=$i; print $9, t}' /proc/stat; }

measure() {  # condition label
  local label="$1" before after
  before=$(cpu_jiffies)
  printf '%-10s %5s %9s %9s %9s %12s\n' "$label" nodes default "1 thread" "2 threads" "default/1"
  for c in $CASES; do
    local n="${c%%:*}" d="${c##*:}"
    declare -A runs=([0]="" [1]="" [2]="")
    for ((r = 0; r < RUNS; r++)); do
      for t in 0 1 2; do
        local s
        s=$("$BIN" --nodes "$n" --duration "$d" --threads "$t" | sed -n 's/.*speed=\([0-9.]*\) x.*/\1/p')
        runs[$t]+="$s "
      done
    done
    python3 - "$label" "$n" "${runs[0]}" "${runs[1]}" "${runs[2]}" <<'PY'
import statistics, sys
label, n, *arms = sys.argv[1:]
med = [statistics.median(float(v) for v in a.split()) for a in arms]
print(f"{label:<10} {n:>5} {med[0]:8.2f}x {med[1]:8.2f}x {med[2]:8.2f}x {med[0] / med[1]:11.2f}")
PY
  done
  after=$(cpu_jiffies)
  python3 -c "
b, a = '$before'.split(), '$after'.split()
st, tot = int(a[0]) - int(b[0]), int(a[1]) - int(b[1])
print(f'$label: steal {100 * st / max(tot, 1):.1f} % of the CPU time')"
}

echo "thread_tuning: $(nproc) cores, $RUNS runs each, medians; $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
measure as-is
if [ "$LOAD" = 1 ]; then
  command -v stress-ng >/dev/null || { echo "thread_tuning: stress-ng is missing (apt-get install stress-ng)" >&2; exit 2; }
  stress-ng --cpu 2 --quiet &
  stress=$!
  trap 'kill $stress 2>/dev/null || true' EXIT
  measure stress-ng
fi
