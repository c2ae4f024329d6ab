#!/usr/bin/env bash
# ThreadSanitizer run of everything that shares memory between threads. Builds
# build/tsan (scripts/build.sh tsan: the emulator and the unit-test binary only,
# no GNU Radio parts) and runs, under TSan:
#   - the unit tests of the engine (worker pool, engine, ledger, mixer), the
#     external-transceiver module (hub, node link, message channel, remote and
#     sample-port transceivers, handshake, stalls), the servers and what they
#     share (port slots, agent control, dashboard server and viewer queue, live
#     view, SPSC ring) and the trace writers;
#   - integration tests that run many threads at once against that binary:
#     every face busy on two worker threads with dashboard viewers
#     (test_all_faces_at_once), the split architecture with its children and a
#     samples-role program (test_split_architecture), the net ports
#     (test_delivery, test_errors_and_accounting).
# A race, a lock-order inversion or a thread leak fails the test it happens in
# (halt_on_error). Extra arguments go to ctest (e.g. -R WorkerPool).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh tsan rfsitl rfsitl_unit_tests
# No suppressions: every report so far was fixed at its cause.
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
unit='WorkerPool|Engine[A-Za-z]*|FrameLedger|Mixer|External[A-Za-z]*|External/[A-Za-z]+'
unit+='|PortSlot|AgentControl|Dashboard[A-Za-z]*|LiveView|SpscRing|PcapTrace|SigmfRecorder'
unit+='|LocationPortSource|VehicleLink|MavlinkEndpoint'
integration='test_all_faces_at_once|test_split_architecture|test_delivery|test_errors_and_accounting'
ctest --test-dir build/tsan --output-on-failure -j "$(nproc)" \
  -R "^(($unit)\.|integration\.($integration)$)" "$@"
