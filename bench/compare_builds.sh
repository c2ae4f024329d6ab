#!/usr/bin/env bash
# Two builds of rfsitl side by side, alternated run by run so that the
# machine's state weighs on both alike: virtual-time speed (medians of 3), RTT
# of 100 pings (two runs each) and capacity (every node pings a random node
# once a second for 20 s).
#
#   bash bench/compare_builds.sh BEFORE AFTER
#
# BEFORE and AFTER are folders holding `rfsitl`, `rfsitl_virtual_speed` and
# `rfsitl_swarm_load` (e.g. a copy of an older build/release's apps/rfsitl and
# bench/rfsitl_* in one folder, and build/release/apps + build/release/bench
# given as AFTER=build/release: both layouts are found).
set -u
[ $# -eq 2 ] || { echo "usage: bash bench/compare_builds.sh BEFORE AFTER" >&2; exit 2; }
find_bin() {  # folder name
  for p in "$1/$2" "$1/apps/$2" "$1/bench/$2"; do [ -x "$p" ] && { echo "$p"; return; }; done
  echo "compare_builds: no $2 in $1" >&2; exit 2
}
declare -A bin
for side in before after; do
  dir=$([ $side = before ] && echo "$1" || echo "$2")
  for b in rfsitl rfsitl_virtual_speed rfsitl_swarm_load; do bin[$side.$b]=$(find_bin "$dir" $b); done
done
med() { python3 -c "import statistics,sys; print(f'{statistics.median(float(x) for x in sys.argv[1:]):.2f}')" "$@"; }
speed() { "${bin[$1.rfsitl_virtual_speed]}" --nodes $2 --duration $3 --threads $4 | sed -n 's/.*speed=\([0-9.]*\) x.*/\1/p'; }

echo "== virtual speed, medians of 3"
for c in "15 20" "64 5"; do
  set -- $c
  for t in 0 1; do
    b=""; a=""
    for r in 1 2 3; do b+=" $(speed before $1 $2 $t)"; a+=" $(speed after $1 $2 $t)"; done
    echo "N=$1 D=$2 threads=$t: before $(med $b)x [$b ]  after $(med $a)x [$a ]"
  done
done

# Port bases below the ephemeral range (32768-60999), apart for each run, so
# that one run's ports never meet the last one's connections in TIME_WAIT.
next_base=20000
take_base() { base=$next_base; next_base=$((next_base + 2000)); }

rtt() {  # side nodes
  take_base
  "${bin[$1.rfsitl]}" run --nodes $2 --no-dashboard --net-base $base --loc-base $((base + 3)) \
    --stats-interval 0 >/dev/null 2>&1 &
  local pid=$!
  "${bin[$1.rfsitl]}" ping --src 1 --dst $2 --count 100 --net-base $base --connect-timeout 20 2>&1 |
    grep -o "mean=.*" | head -1
  kill -INT $pid; wait $pid 2>/dev/null
}
echo "== RTT node 1 -> N, 100 pings (ms)"
for n in 6 15; do
  for r in 1 2; do echo "N=$n run $r: before $(rtt before $n) | after $(rtt after $n)"; done
done

capacity() {  # side nodes
  take_base
  local d; d=$(mktemp -d)
  "${bin[$1.rfsitl]}" run --nodes $2 --no-dashboard --net-base $base --loc-base $((base + 3)) \
    --stats-interval 0 --summary-json $d/s.json >$d/run.log 2>&1 &
  local pid=$!
  "${bin[$1.rfsitl_swarm_load]}" --nodes $2 --net-base $base --duration 20 --json $d/load.json \
    >$d/load.log 2>&1
  kill -INT $pid; wait $pid 2>/dev/null
  echo -n "N=$2 $1: "
  python3 -c "
import json; l = json.load(open('$d/load.json')); s = json.load(open('$d/s.json'))
print(f\"delivery {l['delivery_ratio']:.3f}, worst lag {1e3 * s['max_lag_s']:.1f} ms, late ticks {s['late_ticks']}\")" \
    2>/dev/null || { echo "failed:"; tail -n 3 $d/run.log $d/load.log; }
  rm -rf $d
}
echo "== capacity, 20 s"
for n in 64 128; do capacity before $n; capacity after $n; done
