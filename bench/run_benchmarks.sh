#!/usr/bin/env bash
# The benchmark suite: set up, build (release), measure, and write CSV files, PNG
# plots and summary.md into out/bench/ (the paper's numbers beside ours).
#
#   bash bench/run_benchmarks.sh            # full run; on 2 cores the stages fig4 (in-process
#                                           # only) fig5 capacity capacity_fading ofdm_native
#                                           # ofdm_ip virtual mix took 18.5 minutes
#   QUICK=1 bash bench/run_benchmarks.sh    # smoke run: fewer nodes, shorter stages
#
# Always: the air-time floor, one 80-byte frame + one 8-byte ack at 1 Msps (rfsitl_airtime).
# Stages (STAGES="fig4 fig5 capacity capacity_fading ofdm_native ofdm_ip virtual receivers mobility mix
# stage_cost dashboard overload fading_per mac" by default, and ip; any subset):
#   fig4      Fig. 4 analogue: CDF of COUNT RTTs at N = 6, one curve per architecture
#   fig5      Fig. 5 analogue: RTT mean/p10/p90 against N (ping node 1 <-> node N)
#   capacity  every node pings a random other node once per second for CAP_SECONDS of
#             real time (rfsitl_swarm_load); largest N that keeps real time (definition:
#             bench/bench_collect.py) and its delivery ratio
#   capacity_fading  the same with the delay stage, four taps and Rician fading on every
#             tap of every link (a scenario with `nodes: N`), N = CAPF_NODES
#   ofdm_native  the same load on 802.11a/g OFDM at its native 20 Msps, 24 Mbit/s frames,
#             ticks of OFDM_TICK_US, N = OFDM_NODES: real time, lag, delivery, CPU per node
#   ofdm_ip   the ofdm_native scenario with IP on every node (N = OFDM_IP_NODES) and, beside
#             the pings, iperf3 UDP at OFDM_IP_KBPS from node 1 to node 2 (1500-byte IP
#             packets) for the whole load, MAC OFDM_IP_MAC; adds iperf3's goodput, loss and
#             jitter (root, iperf3; skipped with a message otherwise)
#   virtual   simulated seconds per wall second, VIRT_NODES nodes, 1 frame/node/s
#   receivers every PHY's receiver on one core: Msps of thread CPU time on noise and on
#             back-to-back 80-byte frames (rfsitl_receiver_throughput, RX_SECONDS of signal)
#   mobility  share of the wall time spent moving MOB_NODES random-waypoint nodes in
#             virtual time, every node pinging a random node once a second (frame and
#             scheduled answer), at 10 ms and 1 ms updates (rfsitl_mobility_share)
#   mix       channel::mix complex MAC/s beside the CPU's measured peak
#   stage_cost each channel stage's cost on the channel alone: ns per link and sample,
#             ns per link recomputed when a node moves (rfsitl_stage_cost)
#   dashboard CPU, peak memory and lag of a DASH_NODES-node run with the dashboard off,
#             on, and with 1 and 4 WebSocket viewers (bench/dashboard_cost.py)
#   overload  64 nodes flooding frames for OVL_SECONDS with 500 idle connections and 4 slow
#             or silent dashboard viewers: peak memory against a ceiling computed from the
#             queue bounds, and the books of every frame (bench/overload.py; fails the
#             stage, not the run, when the ceiling or the books do not hold)
#   fading_per PER of gmsk and dsss in Rayleigh block fading (the fading stage, the receiver
#             hopping between frames) against the AWGN curve averaged over Exp(1) SNR, at mean
#             SNR 0..30 dB, FADING_FRAMES frames per point (rfsitl_fading_per; 160 s of CPU at
#             20000, run on both cores); CSV, PNG and log in OUT/fading_per/ (fails the stage,
#             not the run, when a gap exceeds 1 dB)
#   mac       the MACs under saturation (N = 2, 4, 8, 16 senders to one sink; none, tdma,
#             csma) beside Bianchi's model, MAC_SECONDS virtual seconds per run
#             (rfsitl_mac_saturation); table, CSV and PNG in OUT/mac/
#   ip        iperf3 TCP and UDP between two IP nodes per PHY and MAC beside the air-time and
#             csma bounds (bench/ip_throughput.py; root, iperf3); not in the default list
# Environment (defaults for the full run; QUICK=1 picks shorter ones):
#   OUT=out/bench  COUNT=100  FIG5_NODES="2 3 ... 15 32 64"  CAP_NODES="8 16 24 32 48 64 96 128 160"
#   CAPF_NODES="32 48 64"  OFDM_NODES="2 4 8 12"  OFDM_TICK_US=100  OFDM_TICK_SAMPLES=
#   OFDM_IP_NODES=8  OFDM_IP_KBPS=5000  OFDM_IP_MAC=none
#   BIN=build/release/apps/rfsitl
#   CAP_SECONDS=60  VIRT_NODES=15  VIRT_SECONDS=60  MOB_NODES=64  MOB_SECONDS=60,10
#   MIX_SECONDS=0.2  RX_SECONDS=1  OVL_SECONDS=60  FADING_FRAMES=20000  PORT_BASE=20000
#   FIG4_ARCHS=inprocess  NO_BUILD=1 (skip setup and build)  PORT_STRIDE=1000  PORT_SLOTS=40
# Every emulator binds 127.0.0.1, gets its own port range (PORT_BASE + PORT_STRIDE k) and is
# always stopped (SIGINT, then SIGKILL after 30 s), also when this script fails.
set -euo pipefail
cd "$(dirname "$0")/.."
T_START=$(date +%s)

QUICK="${QUICK:-0}"
if [ "$QUICK" = 1 ]; then
  D_COUNT=20 D_FIG5="2 3 6 10 15 32" D_CAP="8 16 32" D_CAPF="16 32" D_OFDM="2 8" D_CAP_S=15
  D_VIRT_S=10 D_MIX_S=0.05 D_RX_S=0.2
  D_DASH_S=5 D_MOB_S=10,5 D_OVL_S=15 D_FADING=2000 D_MAC_S=10
else
  D_COUNT=100 D_FIG5="$(seq -s ' ' 2 15) 32 64" D_CAP="8 16 24 32 48 64 96 128 160" D_CAPF="32 48 64"
  D_OFDM="2 4 8 12"
  D_CAP_S=60
  D_VIRT_S=60 D_MIX_S=0.2 D_RX_S=1 D_DASH_S=20 D_MOB_S=60,10 D_OVL_S=60 D_FADING=20000 D_MAC_S=60
fi
OUT="${OUT:-out/bench}"
COUNT="${COUNT:-$D_COUNT}"
FIG5_NODES="${FIG5_NODES:-$D_FIG5}"
CAP_NODES="${CAP_NODES:-$D_CAP}"
CAPF_NODES="${CAPF_NODES:-$D_CAPF}"
OFDM_NODES="${OFDM_NODES:-$D_OFDM}"
OFDM_IP_NODES="${OFDM_IP_NODES:-8}"
OFDM_IP_KBPS="${OFDM_IP_KBPS:-5000}"
OFDM_IP_MAC="${OFDM_IP_MAC:-none}"
# 100 us = 2000 samples at 20 Msps: 10,000 ticks a second, not 80,000 of 250 samples.
# OFDM_TICK_SAMPLES, if set, gives the tick in samples instead (e.g. 250, as before ticks
# by duration, also for an older build's BIN that lacks tick_us).
OFDM_TICK_US="${OFDM_TICK_US:-100}"
OFDM_TICK_SAMPLES="${OFDM_TICK_SAMPLES:-}"
CAP_SECONDS="${CAP_SECONDS:-$D_CAP_S}"
VIRT_NODES="${VIRT_NODES:-15}"
VIRT_SECONDS="${VIRT_SECONDS:-$D_VIRT_S}"
MIX_SECONDS="${MIX_SECONDS:-$D_MIX_S}"
RX_SECONDS="${RX_SECONDS:-$D_RX_S}"
MOB_NODES="${MOB_NODES:-64}"
MOB_SECONDS="${MOB_SECONDS:-$D_MOB_S}"  # virtual seconds at 10 ms, at 1 ms
PORT_BASE="${PORT_BASE:-20000}"
# Port ranges used in turn: PORT_SLOTS of PORT_STRIDE ports from PORT_BASE (a range
# must hold 10 ports per node: 200 is enough for 16 nodes).
PORT_STRIDE="${PORT_STRIDE:-1000}"
PORT_SLOTS="${PORT_SLOTS:-40}"
STAGES="${STAGES-fig4 fig5 capacity capacity_fading ofdm_native ofdm_ip virtual receivers mobility mix stage_cost dashboard overload fading_per mac}"  # empty: only the report
DASH_NODES="${DASH_NODES:-64}"
DASH_SECONDS="${DASH_SECONDS:-$D_DASH_S}"
OVL_SECONDS="${OVL_SECONDS:-$D_OVL_S}"
FADING_FRAMES="${FADING_FRAMES:-$D_FADING}"
MAC_SECONDS="${MAC_SECONDS:-$D_MAC_S}"
# Architectures of the Fig. 4 CDF. Each name A needs a function fig4_start_A LOG JSON
# that starts that architecture's emulator with 6 nodes via start_emulator (below) or
# its own launcher that sets EMU_PID and NET_BASE the same way:
#   inprocess  built-in GMSK transceivers on the emulator's worker threads
#   split      the same transceivers, one `rfsitl node` process each
#   gnuradio   six GNU Radio flowgraphs (examples/gnuradio/gmsk_node.py), stock
#              gr-digital GMSK, each serving its own net port (needs scripts/build_gr.sh)
FIG4_ARCHS="${FIG4_ARCHS:-inprocess split gnuradio}"

mkdir -p "$OUT"/fig4 "$OUT"/fig5 "$OUT"/capacity
# Report only (STAGES empty): keep the timings and run facts of the run that measured.
[ -z "$STAGES" ] || rm -f "$OUT/timings.csv" "$OUT/run_info.csv"
T_LAST=$T_START
# Records how long the part since the last mark took, and the 1-minute load average
# at its end: other processes on the same cores make every real-time result worse.
mark() {
  local now load
  now=$(date +%s)
  load=$(cut -d' ' -f1 /proc/loadavg)
  echo "bench: $1 took $((now - T_LAST)) s (load average $load)"
  echo "$1,$((now - T_LAST)),$load" >>"$OUT/timings.csv"
  T_LAST=$now
}
LOAD_BEFORE=$(cut -d' ' -f1 /proc/loadavg)
if [ "${NO_BUILD:-0}" != 1 ]; then
  bash scripts/setup.sh
  bash scripts/build.sh release
fi
BIN="${BIN:-build/release/apps/rfsitl}"  # another build's emulator, to compare
BENCH=build/release/bench
PY=/usr/bin/python3
stage() { [[ " $STAGES " == *" $1 "* ]]; }

# --- emulator lifecycle -----------------------------------------------------------
EMU_PID=""
NET_BASE=""
RUN_INDEX=0

stop_emulator() {
  [ -n "$EMU_PID" ] || return 0
  kill -INT "$EMU_PID" 2>/dev/null || true
  for _ in $(seq 300); do
    kill -0 "$EMU_PID" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$EMU_PID" 2>/dev/null; then
    echo "bench: emulator $EMU_PID ignored SIGINT for 30 s; killing it" >&2
    kill -KILL "$EMU_PID" 2>/dev/null || true
  fi
  wait "$EMU_PID" 2>/dev/null || true
  EMU_PID=""
}
trap 'stop_gnuradio; stop_emulator' EXIT
trap 'stop_gnuradio; stop_emulator; exit 130' INT TERM

# launch_emulator LOG JSON ARGS...: starts `rfsitl run ARGS` in the background on the
# next port range (PORT_BASE + PORT_STRIDE k); sets EMU_PID and NET_BASE.
launch_emulator() {
  local log="$1" json="$2"
  shift 2
  local base=$((PORT_BASE + PORT_STRIDE * (RUN_INDEX % PORT_SLOTS)))
  RUN_INDEX=$((RUN_INDEX + 1))
  NET_BASE=$((base + 3))
  "$BIN" run "$@" --net-base "$NET_BASE" --loc-base $((base + 6)) --bind 127.0.0.1 \
    --dashboard-port "$((base + 1))" --stats-interval 1 --summary-json "$json" >"$log" 2>&1 &
  EMU_PID=$!
}

# wait_for_line LOG TEXT: 0 once the emulator printed TEXT, 1 if it exited or 60 s passed.
wait_for_line() {
  for _ in $(seq 600); do
    grep -q "$2" "$1" 2>/dev/null && return 0
    kill -0 "$EMU_PID" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}

# start_emulator LOG JSON ARGS...: launches and waits for "rfsitl: ready"; tries three
# port ranges (a port may be taken by someone else).
start_emulator() {
  local log="$1" json="$2"
  shift 2
  for _attempt in 1 2 3; do
    launch_emulator "$log" "$json" "$@"
    wait_for_line "$log" "rfsitl: ready" && return 0
    echo "bench: emulator did not get ready on net base $NET_BASE (tail of $log):" >&2
    tail -3 "$log" >&2 || true
    stop_emulator
  done
  return 1
}

fig4_start_inprocess() { start_emulator "$1" "$2" --nodes 6; }
fig4_start_split() { start_emulator "$1" "$2" --nodes 6 --arch split; }

# Six GNU Radio nodes: the emulator opens its ports and waits for them to join, so
# the flowgraphs start between its "waiting" line and its "ready" line.
GR_PIDS=()
stop_gnuradio() {
  [ ${#GR_PIDS[@]} -gt 0 ] || return 0
  kill -INT "${GR_PIDS[@]}" 2>/dev/null || true
  sleep 1
  kill -KILL "${GR_PIDS[@]}" 2>/dev/null || true
  wait "${GR_PIDS[@]}" 2>/dev/null || true
  GR_PIDS=()
}
fig4_start_gnuradio() {
  if ! $PY -c "from gnuradio import rfsitl" 2>/dev/null; then
    echo "bench: gnuradio curve skipped: the OOT module is not installed (bash scripts/build_gr.sh)"
    return 1
  fi
  local log="$1" json="$2"
  launch_emulator "$log" "$json" --nodes 6 --phy external
  wait_for_line "$log" "waiting up to" || { tail -3 "$log" >&2; return 1; }
  for id in 1 2 3 4 5 6; do
    $PY examples/gnuradio/gmsk_node.py --socket "/tmp/rfsitl-$NET_BASE.sock" --id "$id" \
      --net-base "$NET_BASE" >"${log%.log}_gr$id.log" 2>&1 &
    GR_PIDS+=($!)
  done
  wait_for_line "$log" "rfsitl: ready" && return 0
  echo "bench: GNU Radio nodes did not all join (tail of $log):" >&2
  tail -3 "$log" >&2 || true
  return 1
}

# --- stages -----------------------------------------------------------------------
# The air-time floor is always measured: every RTT is also shown as a multiple of it.
"$BENCH"/rfsitl_airtime --size 80 --ack-size 8 --sample-rate 1e6 | tee "$OUT/airtime.csv"
FLOOR_MS=$(tail -1 "$OUT/airtime.csv" | cut -d, -f7)
[ -z "$STAGES" ] || mark setup

if stage fig4; then
  echo "== Fig. 4: CDF of $COUNT RTTs at N = 6 ($FIG4_ARCHS)"
  for arch in $FIG4_ARCHS; do
    rm -f "$OUT/fig4/rtt_$arch.csv"
    if "fig4_start_$arch" "$OUT/fig4/emulator_$arch.log" "$OUT/fig4/summary_$arch.json"; then
      printf "%s: " "$arch"
      "$BIN" ping --src 1 --dst 6 --count "$COUNT" --size 80 --timeout 2 --quiet \
        --net-base "$NET_BASE" --csv "$OUT/fig4/rtt_$arch.csv" || echo "ping failed"
    fi
    stop_emulator
    stop_gnuradio
  done
  mark fig4
fi

if stage fig5; then
  echo "== Fig. 5: RTT against N = $FIG5_NODES ($COUNT packets each, node 1 -> node N)"
  rm -f "$OUT/fig5_rtt_vs_n.csv"
  for n in $FIG5_NODES; do
    log="$OUT/fig5/emulator_$n.log" json="$OUT/fig5/summary_$n.json" rtt="$OUT/fig5/rtt_$n.csv"
    rm -f "$json" "$rtt"
    if start_emulator "$log" "$json" --nodes "$n"; then
      "$BIN" ping --src 1 --dst "$n" --count "$COUNT" --size 80 --timeout 2 --quiet \
        --net-base "$NET_BASE" --csv "$rtt" >/dev/null || echo "bench: ping at N=$n failed"
    fi
    stop_emulator
    "$PY" bench/bench_collect.py rtt-row --n "$n" --ping-csv "$rtt" --summary-json "$json" \
      --floor-ms "$FLOOR_MS" --out "$OUT/fig5_rtt_vs_n.csv"
  done
  mark fig5
fi

# cpu_seconds PID: user + system CPU seconds of the process so far (all its threads).
cpu_seconds() {
  awk -v tck="$(getconf CLK_TCK)" '{ print ($14 + $15) / tck }' "/proc/$1/stat"
}

# capacity_run NAME NODES [SCENARIO_OF_N [SIDE_LOAD]]: the capacity loop, one row per N
# into $OUT/NAME.csv, logs in $OUT/NAME/. SCENARIO_OF_N, if given, is a function that
# writes the scenario file for N nodes and prints its path; otherwise --nodes N.
# SIDE_LOAD, if given, is a function called as `SIDE_LOAD start N` once the emulator is
# ready (before the load) and `SIDE_LOAD finish N` after it; it prints extra
# arguments for bench_collect.py's capacity-row.
capacity_run() {
  local name="$1" nodes="$2" scenario_of="${3:-}" side="${4:-}"
  mkdir -p "$OUT/$name"
  rm -f "$OUT/$name.csv"
  for n in $nodes; do
    log="$OUT/$name/emulator_$n.log" json="$OUT/$name/summary_$n.json"
    load="$OUT/$name/load_$n.json"
    rm -f "$json" "$load"
    from=0 to=0
    if [ -n "$scenario_of" ]; then
      set -- "$("$scenario_of" "$n")"
    else
      set -- --nodes "$n"
    fi
    cpu=() cpu0="" wall0="" side_args=()
    if start_emulator "$log" "$json" "$@"; then
      [ -z "$side" ] || "$side" start "$n"
      from=$(wc -l <"$log")
      cpu0=$(cpu_seconds "$EMU_PID") wall0=$(date +%s.%N)
      "$BENCH"/rfsitl_swarm_load --nodes "$n" --net-base "$NET_BASE" --duration "$CAP_SECONDS" \
        --seed "$n" --json "$load" --csv "$OUT/$name/pings_$n.csv" ||
        echo "bench: load at N=$n failed"
      to=$(wc -l <"$log")
      [ -z "$side" ] || read -r -a side_args <<<"$("$side" finish "$n")"
      cpu=(--cpu-s "$(awk -v a="$(cpu_seconds "$EMU_PID")" -v b="$cpu0" 'BEGIN { print a - b }')"
        --cpu-wall-s "$(awk -v a="$(date +%s.%N)" -v b="$wall0" 'BEGIN { print a - b }')")
    fi
    stop_emulator
    "$PY" bench/bench_collect.py capacity-row --n "$n" --load-json "$load" --emu-log "$log" \
      --from-line "$((from + 1))" --to-line "$to" --load-seconds "$CAP_SECONDS" \
      --summary-json "$json" "${cpu[@]}" "${side_args[@]}" \
      --floor-ms "$FLOOR_MS" --out "$OUT/$name.csv" --lag-csv "$OUT/$name/lag_$n.csv"
  done
}

# The capacity_fading scenario for N nodes: the default formation and the
# paper's path loss, then the delay stage, four taps 100 ns and 3 dB apart
# (Colosseum's four non-zero taps per link) and Rician fading (K = 6 dB, 32
# sinusoids on a 10 kHz grid) on every tap of every link.
fading_scenario_of() {
  local file="$OUT/capacity_fading/scenario_$1.yaml"
  cat >"$file" <<YAML
name: capacity-fading-$1
channel:
  stages:
    - {type: path_loss, model: paper}
    - {type: delay}
    - type: multipath
      profile: taps
      taps:
        - {delay_ns: 0, gain_db: 0}
        - {delay_ns: 100, gain_db: -3}
        - {delay_ns: 200, gain_db: -6}
        - {delay_ns: 300, gain_db: -9}
    - {type: fading, model: rician, k_db: 6}
nodes: $1
YAML
  echo "$file"
}

# The ofdm_native scenario for N nodes: the default formation and the paper's
# path loss, 802.11a/g at 24 Mbit/s and its own 20 Msps, ticks by duration.
# OFDM_STAGE (default ofdm_native) names the folder; OFDM_EXTRA is appended.
ofdm_scenario_of() {
  local stage="${OFDM_STAGE:-ofdm_native}"
  local file="$OUT/$stage/scenario_$1.yaml" tick="tick_us: $OFDM_TICK_US"
  [ -z "$OFDM_TICK_SAMPLES" ] || tick="tick_samples: $OFDM_TICK_SAMPLES"
  cat >"$file" <<YAML
name: $stage-$1
time: {sample_rate_hz: 20e6, $tick}
phy: {type: ofdm, rate_mbps: 24}
nodes: $1
${OFDM_EXTRA:-}
YAML
  echo "$file"
}

# iperf_side start|finish N: iperf3 UDP at OFDM_IP_KBPS from node 1's namespace to node
# 2's for CAP_SECONDS. start waits (up to 30 s) until node 1 reaches node 2 across the
# radio and for the server's listening socket; finish waits for the client and prints
# bench_collect's --iperf-json argument.
IPERF_SERVER="" IPERF_CLIENT=""
iperf_side() {
  local ns="rfsitl-$NET_BASE" json="$OUT/ofdm_ip/iperf_$2.json"
  if [ "$1" = start ]; then
    rm -f "$json"
    for _ in $(seq 30); do
      ip netns exec "$ns-1" ping -c 1 -W 1 10.77.0.2 >/dev/null 2>&1 && break
    done
    ip netns exec "$ns-2" iperf3 -s -1 >/dev/null 2>&1 &
    IPERF_SERVER=$!
    for _ in $(seq 100); do
      ip netns exec "$ns-2" ss -Hlnu 'sport = :5201' 2>/dev/null | grep -q . && break
      ip netns exec "$ns-2" ss -Hlnt 'sport = :5201' 2>/dev/null | grep -q . && break
      sleep 0.05
    done
    ip netns exec "$ns-1" iperf3 -c 10.77.0.2 -u -l 1472 -b "${OFDM_IP_KBPS}k" \
      -t "$CAP_SECONDS" -J >"$json" 2>&1 &
    IPERF_CLIENT=$!
  else
    wait "$IPERF_CLIENT" || echo "bench: iperf3 client at N=$2 failed (see $json)" >&2
    kill "$IPERF_SERVER" 2>/dev/null || true
    wait "$IPERF_SERVER" 2>/dev/null || true
    echo "--iperf-json $json"
  fi
}

if stage capacity; then
  echo "== Capacity: every node pings a random other node once per second, $CAP_SECONDS s" \
    "of real time, N = $CAP_NODES"
  capacity_run capacity "$CAP_NODES"
  mark capacity
fi

if stage capacity_fading; then
  echo "== Capacity with 4-tap Rician fading on every link: the same load, N = $CAPF_NODES"
  mkdir -p "$OUT/capacity_fading"
  capacity_run capacity_fading "$CAPF_NODES" fading_scenario_of
  mark capacity_fading
fi

if stage ofdm_native; then
  echo "== 802.11a/g at 20 Msps, 24 Mbit/s, ticks of $OFDM_TICK_US us: the capacity load," \
    "N = $OFDM_NODES"
  mkdir -p "$OUT/ofdm_native"
  capacity_run ofdm_native "$OFDM_NODES" ofdm_scenario_of
  mark ofdm_native
fi

if stage ofdm_ip; then
  echo "== 802.11a/g at 20 Msps with IP on every node: the capacity load plus iperf3 UDP at" \
    "$OFDM_IP_KBPS kbit/s from node 1 to node 2, MAC $OFDM_IP_MAC, N = $OFDM_IP_NODES"
  if [ "$(id -u)" != 0 ] || ! command -v iperf3 >/dev/null; then
    echo "bench: ofdm_ip skipped: needs root and iperf3 (bash scripts/setup.sh installs it)"
  else
    mkdir -p "$OUT/ofdm_ip"
    OFDM_STAGE=ofdm_ip OFDM_EXTRA="ip: {enabled: true}
mac: {type: $OFDM_IP_MAC}" \
      capacity_run ofdm_ip "$OFDM_IP_NODES" ofdm_scenario_of iperf_side
  fi
  mark ofdm_ip
fi

if stage virtual; then
  echo "== Virtual-time speed: N = $VIRT_NODES, $VIRT_SECONDS simulated s, 1 frame/node/s"
  rm -f "$OUT/virtual_speed.csv"
  for n in $VIRT_NODES; do
    "$BENCH"/rfsitl_virtual_speed --nodes "$n" --duration "$VIRT_SECONDS" \
      --csv "$OUT/virtual_speed.csv"
    # The same with Rayleigh fading on every link, printed beside the flat channel's.
    "$BENCH"/rfsitl_virtual_speed --nodes "$n" --duration "$VIRT_SECONDS" --fading rayleigh \
      --csv "$OUT/virtual_speed.csv"
    # And a TDL fading channel: propagation delay, TR 38.901 TDL-C taps, each fading.
    "$BENCH"/rfsitl_virtual_speed --nodes "$n" --duration "$VIRT_SECONDS" --multipath tdl_c \
      --fading rayleigh --csv "$OUT/virtual_speed.csv"
  done
  mark virtual
fi

if stage receivers; then
  echo "== Receiver throughput on one core: $RX_SECONDS s of signal per measurement"
  "$BENCH"/rfsitl_receiver_throughput --seconds "$RX_SECONDS" --csv "$OUT/receiver_throughput.csv"
  mark receivers
fi

if stage mobility; then
  echo "== Mobility's share: N = $MOB_NODES random waypoint, $MOB_SECONDS virtual s at 10 ms, 1 ms"
  rm -f "$OUT/mobility_share.csv"
  "$BENCH"/rfsitl_mobility_share --nodes "$MOB_NODES" --update 0.01,0.001 \
    --duration "$MOB_SECONDS" --runs 3 --csv "$OUT/mobility_share.csv"
  mark mobility
fi

if stage mix; then
  echo "== Mixing kernel against the CPU's peak"
  "$BENCH"/rfsitl_mix_bench --seconds "$MIX_SECONDS" --csv "$OUT/mix_kernel.csv"
  mark mix
fi

if stage stage_cost; then
  echo "== Channel stages: ns per link and sample, ns per link update"
  "$BENCH"/rfsitl_stage_cost --csv "$OUT/stage_cost.csv"
  mark stage_cost
fi

if stage dashboard; then
  echo "== Dashboard cost: N = $DASH_NODES, $DASH_SECONDS s per configuration"
  "$PY" bench/dashboard_cost.py --bin "$BIN" --port-base "$PORT_BASE" --nodes "$DASH_NODES" --seconds "$DASH_SECONDS" \
    --viewers 1 4 --csv "$OUT/dashboard_cost.csv"
  mark dashboard
fi

if stage overload; then
  echo "== Bounded under overload: 64 flooding nodes, 500 idle connections, 4 slow viewers," \
    "$OVL_SECONDS s"
  rm -f "$OUT/overload.csv"
  "$PY" bench/overload.py --bin "$BIN" --duration "$OVL_SECONDS" --net-base $((PORT_BASE + 3)) \
    --loc-base $((PORT_BASE + 6)) --dashboard-port $((PORT_BASE + 1)) \
    --csv "$OUT/overload.csv" --log "$OUT/overload_emulator.log" ||
    echo "bench: overload: the ceiling or the books did not hold (see above)"
  mark overload
fi

if stage fading_per; then
  echo "== PER in Rayleigh block fading against its reference: gmsk, dsss, $FADING_FRAMES frames" \
    "per point"
  mkdir -p "$OUT/fading_per"
  "$BENCH"/rfsitl_fading_per --frames "$FADING_FRAMES" --csv "$OUT/fading_per/fading_per.csv" |
    tee "$OUT/fading_per/fading_per.log" ||
    echo "bench: fading_per: a gap exceeds 1 dB or a run did not finish (see above)"
  "$PY" bench/plot_fading_per.py "$OUT/fading_per/fading_per.csv" \
    -o "$OUT/fading_per/fading_per.png" || echo "bench: fading_per: plot failed"
  mark fading_per
fi

if stage mac; then
  echo "== MACs under saturation beside Bianchi's model: $MAC_SECONDS virtual s per run"
  mkdir -p "$OUT/mac"
  "$BENCH"/rfsitl_mac_saturation --seconds "$MAC_SECONDS" --csv "$OUT/mac/mac_saturation.csv" |
    tee "$OUT/mac/mac_saturation.log"
  "$PY" bench/plot_mac_saturation.py "$OUT/mac/mac_saturation.csv" \
    -o "$OUT/mac/mac_saturation.png" || echo "bench: mac: plot failed"
  mark mac
fi

if stage ip; then
  echo "== IP throughput: iperf3 TCP and UDP between two IP nodes, per PHY and MAC"
  mkdir -p "$OUT/ip"
  "$PY" bench/ip_throughput.py --bin "$BIN" --bench-dir "$BENCH" \
    --csv "$OUT/ip/ip_throughput.csv" | tee "$OUT/ip/ip_throughput.log" ||
    echo "bench: ip: failed (needs root and iperf3)"
  mark ip
fi

# --- report -----------------------------------------------------------------------
"$PY" bench/bench_plots.py "$OUT"
T_END=$(date +%s)
if [ -n "$STAGES" ]; then
  printf "key,value\nquick,%s\nwall_s,%s\nload_before,%s\nstages,%s\ncap_seconds,%s\n%s\n" \
    "$QUICK" "$((T_END - T_START))" "$LOAD_BEFORE" "$STAGES" "$CAP_SECONDS" \
    "ofdm_tick,${OFDM_TICK_SAMPLES:+$OFDM_TICK_SAMPLES samples}${OFDM_TICK_SAMPLES:-$OFDM_TICK_US us}" \
    >"$OUT/run_info.csv"
fi
"$PY" bench/bench_summary.py "$OUT" >"$OUT/summary.md"
echo
cat "$OUT/summary.md"
echo "bench: results in $OUT/ ($((T_END - T_START)) s)"
