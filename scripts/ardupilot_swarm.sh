#!/usr/bin/env bash
# Three ArduPilot SITL copters, and rfsitl following them over MAVLink
# (scenarios/ardupilot_swarm.yaml). Copter 3 then takes off and flies 600 m
# north, out of the others' radio range, while `rfsitl ping` measures the links
# 1 -> 2 and 1 -> 3 every few seconds: 1 -> 3 goes from no loss to no answer.
#
#   bash scripts/ardupilot_swarm.sh
#
# Needs root (it makes a network namespace of its own: arducopter listens on
# every interface, so everything here runs inside that namespace, on its
# loopback only) and ArduPilot's copter SITL:
#   ARDUCOPTER=/path/to/arducopter  default: `arducopter` on PATH
#                                   (ArduPilot: ./waf configure --board sitl && ./waf copter,
#                                   then build/sitl/bin/arducopter)
#   ARDUPILOT_PARAMS=/path/copter.parm  default: Tools/autotest/default_params/copter.parm
#                                   of the ArduPilot tree the binary was built in
#   RFSITL_BIN                      default: build/release/apps/rfsitl, else build/asan/apps/rfsitl
#   FLY=0                           only start everything and measure for DURATION seconds
#   DURATION=60                     seconds to measure when FLY=0; after a flight, 10 more
#   NORTH=600 SPEED=12 ALT=30       copter 3's flight: metres north, m/s, metres up
# Logs go to out/ardupilot_swarm/: copter0..2/arducopter.log, emulator.log, fly.log.
set -euo pipefail
cd "$(dirname "$0")/.."

SCENARIO=scenarios/ardupilot_swarm.yaml
OUT=out/ardupilot_swarm
NS="rfsitl-ap-$$"
PYTHON="${PYTHON:-python3}"
FLY="${FLY:-1}"
DURATION="${DURATION:-60}"
NORTH="${NORTH:-600}"
SPEED="${SPEED:-12}"
ALT="${ALT:-30}"
# The copters' homes, as in the scenario: instance i is node i+1.
HOMES=("43.000800,-78.789000,0,0" "43.000800,-78.786543,0,0" "43.002597,-78.789000,0,0")

die() { echo "ardupilot_swarm: $*" >&2; exit 1; }

# --- what it needs ------------------------------------------------------------
ARDUCOPTER="${ARDUCOPTER:-$(command -v arducopter || true)}"
[ -n "$ARDUCOPTER" ] || die "arducopter not found. Build ArduPilot's copter SITL \
(in an ArduPilot tree: ./waf configure --board sitl && ./waf copter) and put its \
build/sitl/bin on PATH, or set ARDUCOPTER=/path/to/arducopter."
[ -x "$ARDUCOPTER" ] || die "ARDUCOPTER=$ARDUCOPTER is not an executable file."
ARDUCOPTER="$(readlink -f "$ARDUCOPTER")"

# build/sitl/bin/arducopter -> the tree's Tools/autotest/default_params/copter.parm
TREE="$(dirname "$ARDUCOPTER")/../../.."
ARDUPILOT_PARAMS="${ARDUPILOT_PARAMS:-$TREE/Tools/autotest/default_params/copter.parm}"
[ -f "$ARDUPILOT_PARAMS" ] || die "copter defaults not found at $ARDUPILOT_PARAMS; \
set ARDUPILOT_PARAMS to ArduPilot's Tools/autotest/default_params/copter.parm."
ARDUPILOT_PARAMS="$(readlink -f "$ARDUPILOT_PARAMS")"

if [ -z "${RFSITL_BIN:-}" ]; then
  for candidate in build/release/apps/rfsitl build/asan/apps/rfsitl; do
    [ -x "$candidate" ] && RFSITL_BIN="$candidate" && break
  done
fi
if [ -z "${RFSITL_BIN:-}" ] || [ ! -x "$RFSITL_BIN" ]; then
  die "rfsitl not built: run 'bash scripts/build.sh release' or set RFSITL_BIN."
fi
"$RFSITL_BIN" run --help | grep -- --mavlink >/dev/null ||
  die "$RFSITL_BIN has no MAVLink position source (no --mavlink in 'rfsitl run --help'); rebuild it."
[ "$(id -u)" -eq 0 ] || die "needs root for its network namespace (ip netns)."
command -v ip >/dev/null || die "needs ip (Debian: apt-get install iproute2)."

# --- clean-up, whatever happens ---------------------------------------------------
# Every background job is started as `ip netns exec NS PROGRAM &` (ip execs the
# program), so $! is the program itself and a signal reaches it.
PIDS=()
EMU=""
stop() {  # stop PID SIGNAL: signal it, wait up to 10 s, then SIGKILL
  kill "-$2" "$1" 2>/dev/null || return 0
  for _ in $(seq 100); do
    kill -0 "$1" 2>/dev/null || break
    sleep 0.1
  done
  kill -KILL "$1" 2>/dev/null || true
  wait "$1" 2>/dev/null || true
}
cleanup() {
  local status=$?
  trap - EXIT INT TERM
  [ -n "$EMU" ] && stop "$EMU" INT
  for pid in "${PIDS[@]}"; do stop "$pid" TERM; done
  ip netns del "$NS" 2>/dev/null || true
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

in_ns() { ip netns exec "$NS" "$@"; }
listening() { [ -n "$(in_ns ss -Hltn "sport = :$1")" ]; }

ip netns add "$NS"
in_ns ip link set lo up
rm -rf "$OUT"
mkdir -p "$OUT"

# --- three copters ---------------------------------------------------------------
# Instance i serves SERIAL0 on TCP 5760 + 10 i (for a ground station, here
# ardupilot_fly.py) and SERIAL1 on 5762 + 10 i (rfsitl). By default SERIAL0 makes
# the copter wait for a client before it simulates anything; `--serial0 tcp:0`
# keeps the port without the wait, so the copters start on their own. Each one
# runs in a folder of its own: eeprom.bin and logs/ are written to the current
# folder, and -w starts from the defaults file each time.
for i in 0 1 2; do
  dir="$OUT/copter$i"
  mkdir -p "$dir"
  cmd=("$ARDUCOPTER" --model + --speedup 1 -I "$i" --sysid "$((i + 1))" -w
       --defaults "$ARDUPILOT_PARAMS" --home "${HOMES[$i]}" --serial0 tcp:0)
  echo "copter $i: ${cmd[*]}" | tee "$dir/command.txt"
  (cd "$dir" && exec ip netns exec "$NS" "${cmd[@]}") >"$dir/arducopter.log" 2>&1 &
  PIDS+=($!)
done
for i in 0 1 2; do
  port=$((5762 + 10 * i))
  for _ in $(seq 150); do
    listening "$port" && break
    kill -0 "${PIDS[$i]}" 2>/dev/null || { cat "$OUT/copter$i/arducopter.log"; die "copter $i exited"; }
    sleep 0.2
  done
  listening "$port" || die "copter $i: SERIAL1 (TCP $port) not listening after 30 s"
done
echo "copters up: SERIAL1 on 5762, 5772, 5782"

# --- the emulator ---------------------------------------------------------------------
ip netns exec "$NS" "$RFSITL_BIN" run "$SCENARIO" --no-dashboard --summary-json "$OUT/summary.json" \
  >"$OUT/emulator.log" 2>&1 &
EMU=$!
for _ in $(seq 300); do
  grep -q "rfsitl: ready" "$OUT/emulator.log" 2>/dev/null && break
  kill -0 "$EMU" 2>/dev/null || { cat "$OUT/emulator.log"; EMU=""; die "rfsitl exited"; }
  sleep 0.1
done
grep -q "rfsitl: ready" "$OUT/emulator.log" || die "rfsitl not ready after 30 s (see $OUT/emulator.log)"
sed -n '1,/rfsitl: ready/p' "$OUT/emulator.log"

# One line of link quality: 10 pings of 80 bytes from node 1 to each other node
# (ping's summary line; it exits non-zero when every packet is lost).
ping_summary() {
  { in_ns "$RFSITL_BIN" ping --src 1 --dst "$1" --count 10 --interval 0.05 --timeout 0.3 \
      --quiet 2>&1 || true; } | tail -n 1
}
measure() {
  echo "[$(date +%T)] 1->2: $(ping_summary 2)   1->3: $(ping_summary 3)"
}

# --- copter 3 flies away (or we just watch) ------------------------------------------
if [ "$FLY" = 1 ]; then
  echo "copter 3 (instance 2, SERIAL0 5780): take off to $ALT m, fly $NORTH m north at $SPEED m/s"
  ip netns exec "$NS" "$PYTHON" scripts/ardupilot_fly.py --connect tcp:127.0.0.1:5780 --no-arming-checks \
    --north "$NORTH" --alt "$ALT" --speed "$SPEED" >"$OUT/fly.log" 2>&1 &
  FLIGHT=$!
  PIDS+=("$FLIGHT")
  shown=0
  while kill -0 "$FLIGHT" 2>/dev/null; do
    measure
    tail -n "+$((shown + 1))" "$OUT/fly.log" | sed 's/^/  /'
    shown=$(wc -l <"$OUT/fly.log")
    sleep 3
  done
  tail -n "+$((shown + 1))" "$OUT/fly.log" | sed 's/^/  /'
  wait "$FLIGHT" || die "the flight failed (see $OUT/fly.log)"
  DURATION=10
fi
end=$((SECONDS + DURATION))
while [ "$SECONDS" -lt "$end" ]; do
  measure
  sleep 3
done

stop "$EMU" INT
EMU=""
echo
grep " mavlink " "$OUT/emulator.log" | grep -v "so far)" || true
sed -n '/rfsitl summary/,$p' "$OUT/emulator.log"
echo "ardupilot_swarm: logs in $OUT/ (emulator.log, fly.log, copter*/arducopter.log), counters in $OUT/summary.json"
