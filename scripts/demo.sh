#!/usr/bin/env bash
# The main job: set up, build, install and run the six-UAV demo. Six virtual
# UAVs fly a slow circle while `rfsitl ping` (the paper's COM manager) measures
# round-trip times of 80-byte GMSK packets between three pairs of them.
# Results: the RTT lines below, out/demo/rtt_cdf.png, the emulator's per-node
# summary.
#
#   bash scripts/demo.sh [SCENARIO]
# Environment: PREFIX where the program is installed (/usr/local as root,
# else ~/.local); COUNT=100
# pings per pair; NET_BASE=15763, LOC_BASE=15766 and DASHBOARD_PORT move the
# ports (for a second run on the same machine).
#
# Only what the demo needs is set up and built (the program, its manual pages
# and the air-time table); a second run finds all of it in place and starts
# the demo at once. The rest (tests, GNU Radio blocks, benchmarks) comes with
# the README's second command.
set -euo pipefail
cd "$(dirname "$0")/.."
# root installs for everyone; anyone else into ~/.local (on PATH in Debian's
# default profile once it exists).
if [ "$(id -u)" -eq 0 ]; then PREFIX="${PREFIX:-/usr/local}"; else PREFIX="${PREFIX:-$HOME/.local}"; fi
bash scripts/setup.sh --demo
bash scripts/build.sh release rfsitl rfsitl_docs rfsitl_airtime
cmake --install build/release --prefix "$PREFIX" --component program >/dev/null
echo "demo: rfsitl installed in $PREFIX ($("$PREFIX/bin/rfsitl" --version))"

BIN="$PREFIX/bin/rfsitl"
OUT=out/demo
SCENARIO="${1:-scenarios/six_uav.yaml}"
COUNT="${COUNT:-100}"
NET_BASE="${NET_BASE:-15763}"
LOC_BASE="${LOC_BASE:-15766}"
# The dashboard takes 15700, or any free port when that one is taken.
DASH_ARGS=()
[ -n "${DASHBOARD_PORT:-}" ] && DASH_ARGS=(--dashboard-port "$DASHBOARD_PORT")
mkdir -p "$OUT"
rm -f "$OUT"/rtt_*.csv

# The run also writes a Wireshark trace of every frame event, and serves the
# live dashboard at the URL in its banner while it runs.
"$BIN" run "$SCENARIO" --stats-interval 5 --summary-json "$OUT/summary.json" \
  --net-base "$NET_BASE" --loc-base "$LOC_BASE" "${DASH_ARGS[@]}" \
  --pcap "$OUT/demo.pcapng" >"$OUT/emulator.log" 2>&1 &
EMU=$!
FLY=""
cleanup() {
  [ -n "$FLY" ] && kill "$FLY" 2>/dev/null || true
  kill -INT "$EMU" 2>/dev/null || true
}
trap cleanup EXIT
for _ in $(seq 100); do
  grep -q "rfsitl: ready" "$OUT/emulator.log" 2>/dev/null && break
  kill -0 "$EMU" 2>/dev/null || { cat "$OUT/emulator.log"; exit 1; }
  sleep 0.1
done
sed -n '1,/rfsitl: ready/p' "$OUT/emulator.log"
NODES=$(grep -c "^  node" "$OUT/emulator.log")

/usr/bin/python3 scripts/fly_swarm.py --nodes "$NODES" --loc-base "$LOC_BASE" &
FLY=$!
echo
echo "== $NODES UAVs flying; $COUNT pings of 80 bytes per pair (one at a time, as in the paper)"
for pair in "1 2" "3 $NODES" "$((NODES - 1)) 1"; do
  set -- $pair
  printf "node %s -> node %s: " "$1" "$2"
  "$BIN" ping --src "$1" --dst "$2" --count "$COUNT" --size 80 --quiet --net-base "$NET_BASE" \
    --csv "$OUT/rtt_${1}_${2}.csv"
done
kill "$FLY" 2>/dev/null || true
FLY=""
kill -INT "$EMU"
wait "$EMU" || true
trap - EXIT
sed -n '/rfsitl summary/,$p' "$OUT/emulator.log"
# The air-time floor: an 80-byte frame plus an 8-byte ack on the default PHY.
FLOOR_MS=$(build/release/bench/rfsitl_airtime | tail -n 1 | cut -d, -f7)
/usr/bin/python3 scripts/plot_rtt.py "$OUT"/rtt_*.csv -o "$OUT/rtt_cdf.png" --floor-ms "$FLOOR_MS"
echo "demo: emulator log $OUT/emulator.log, counters $OUT/summary.json, Wireshark trace $OUT/demo.pcapng"
echo "demo: run it again (nothing is rebuilt): bash scripts/demo.sh; or the program alone: $BIN run six_uav.yaml"
