#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) into build/fuzz with clang-14 and runs
# each for SECONDS (default 10), one at a time, on a scratch copy of its seed
# corpus (fuzz/corpus/ is never written). Prints a table: target, executions,
# seconds, crashes; exits non-zero on any crash, naming the reproducer.
#   scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. scripts/fuzz.sh 5 net_framing
# Extra libFuzzer flags: FUZZ_FLAGS="-runs=10000000" scripts/fuzz.sh 0
# (SECONDS 0 = no time limit). To go on after a crash (a campaign):
# FUZZ_FLAGS="-fork=1 -ignore_crashes=1" (one fuzzing process at a time still).
# Logs and crash files go to FUZZ_OUT (default build/fuzz): <target>.log and
# crashes/<target>-crash-*; a long campaign beside the suite (which runs this
# script too) takes a folder of its own, e.g. FUZZ_OUT=build/fuzz-campaign.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-10}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] ||
  targets=(net_framing agent_control ethernet_frame location_parser scenario wire_protocol
           dashboard_http dashboard_ws mavlink_parser vehicle_link mobility_trace antenna_pattern
           channel_trace tick_exchange live_view_share link_table campaign)

# clang-14 and libFuzzer (libclang_rt.fuzzer-x86_64.a comes with libclang-rt-14-dev
# on Debian 12), plus the libraries the parsers build with.
PACKAGES=(clang-14 libclang-rt-14-dev cmake ninja-build
  libliquid-dev libfec-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  libboost-dev)
bash scripts/apt_install.sh fuzz "${PACKAGES[@]}"

cmake -S . -B build/fuzz -G Ninja -DRFSITL_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRFSITL_WERROR=OFF -DRFSITL_BUILD_TESTS=OFF \
  -DRFSITL_BUILD_BENCH=OFF >/dev/null
cmake --build build/fuzz -j "$(nproc)" --target "${targets[@]/%/_fuzzer}"

# Allocation stacks of 5 frames: ASan stores every distinct allocation stack
# for the whole run, and with yaml-cpp's deep recursions that took a third
# or more of the scenario target's time (perf); 5 frames ran it 25 % faster
# (45 s each on one corpus). It still slows as it ages: long campaigns of
# scenario and net_framing use -fork=1. Detection is the same; for a
# report's full stacks, run its reproducer with ASAN_OPTIONS=malloc_context_size=30.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:malloc_context_size=5}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
scratch="$(mktemp -d /tmp/rfsitl-fuzz.XXXXXX)"
trap 'rm -rf "$scratch"' EXIT
out="${FUZZ_OUT:-build/fuzz}"
mkdir -p "$out/crashes"
rows=()
failed=0
# Regression first: every crash ever found (fuzz/crashes/<target>/) must now
# pass, also with the dashboard fixture before the engine's first tick.
for t in "${targets[@]}"; do
  [ -d "fuzz/crashes/$t" ] || continue
  for before_run in 0 1; do
    if ! RFSITL_FUZZ_BEFORE_RUN=$before_run build/fuzz/fuzz/"$t"_fuzzer fuzz/crashes/"$t"/* \
      >"$out/$t.regression.log" 2>&1; then
      echo "fuzz: $t: a known crash is back (RFSITL_FUZZ_BEFORE_RUN=$before_run);" \
        "log: $out/$t.regression.log" >&2
      failed=1
    fi
  done
done
# Artifacts of target $t in $out/crashes matching grep's arguments. A "slow
# unit" is one that took over 10 s of wall time, which on a busy machine says
# more about the machine than the parser: counted apart (each is kept, to be
# timed again) and not a failure. Everything else is.
count() { ls "$out/crashes" | grep "^$t-" | grep -c "$@" || true; }
for t in "${targets[@]}"; do
  corpus="$scratch/$t"
  mkdir -p "$corpus"
  cp fuzz/corpus/"$t"/* "$corpus"/
  log="$out/$t.log"
  limit=()
  [ "$seconds" -gt 0 ] && limit=(-max_total_time="$seconds")
  # Each run costs time in proportion to the input's length, and past a few
  # of the parser's units a longer input only repeats them (a MAVLink frame
  # is at most 280 bytes; a location line is parsed on its own; a net frame
  # ends at its terminator): these targets cap inputs below libFuzzer's
  # default of 4096 bytes (a -max_len in FUZZ_FLAGS comes later and wins).
  case "$t" in
    mavlink_parser | location_parser) limit+=(-max_len=1024) ;;
    net_framing) limit+=(-max_len=2048) ;;
  esac
  before=$(count -v -- "-slow-unit-")
  slow_before=$(count -- "-slow-unit-")
  start=$(date +%s.%N)
  rc=0
  # shellcheck disable=SC2086  # FUZZ_FLAGS is a list of flags
  build/fuzz/fuzz/"$t"_fuzzer "${limit[@]}" -print_final_stats=1 -timeout=30 \
    -artifact_prefix="$out/crashes/$t-" ${FUZZ_FLAGS:-} "$corpus" >"$log" 2>&1 || rc=$?
  elapsed=$(echo "$(date +%s.%N) - $start" | bc)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  if [ -z "$execs" ]; then  # a crash prints no final stats: take the last status line
    execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  fi
  crashes=$(( $(count -v -- "-slow-unit-") - before ))
  slow=$(( $(count -- "-slow-unit-") - slow_before ))
  if [ "$rc" -ne 0 ] || [ "$crashes" -gt 0 ]; then
    [ "$crashes" -gt 0 ] || crashes=1
    failed=1
    repro=$(sed -n "s/.*Test unit written to \(.*\)$/\1/p" "$log" | tail -1)
    echo "fuzz: $t: $crashes crash(es) (exit $rc); reproducer: ${repro:-none written}; log: $log" >&2
    grep -E "ERROR:|invariant failed|SUMMARY|what\(\)" "$log" | head -5 >&2 || true
  fi
  rows+=("$(printf '%-16s %14s %9.1f %8s %10s' "$t" "${execs:-?}" "$elapsed" "$crashes" "$slow")")
done
printf '%-16s %14s %9s %8s %10s\n' target executions seconds crashes slow-units
printf '%s\n' "${rows[@]}"
exit "$failed"
