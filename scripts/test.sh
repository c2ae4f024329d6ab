#!/usr/bin/env bash
# Sets up, builds (sanitizers on) and runs every test: unit, integration (the
# real emulator over loopback, GNU Radio nodes included) and the dashboard in
# headless Chromium; then a short libFuzzer run of every parser (scripts/fuzz.sh).
# Extra arguments go to ctest (e.g. -L unit, -R gnuradio).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh asan
# The optimized build too, as the demo makes it: GCC warns of things at -O3
# that it does not see in the sanitized build, and warnings are errors (a
# false -Wstringop-overflow once broke the demo's build and no test saw it).
bash scripts/build.sh release
# SoapySDRServer cannot load a sanitized SoapySDR module (README, "SoapySDR"),
# so test_soapy_remote serves the release build's.
if [ -f build/release/src/soapy/libSoapyRfsitl.so ]; then
  export RFSITL_SOAPY_RELEASE_DIR="$PWD/build/release/src/soapy"
fi
# The GNU Radio blocks: build and install (a no-op when up to date), then their
# own QA tests (blocks against a stand-in emulator, in isolation).
bash scripts/build_gr.sh --test
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build/asan --output-on-failure -j "$(nproc)" "$@"
# Every parser of outside input under libFuzzer (clang, ASan + UBSan) for a few
# seconds each, after replaying every crash found so far (fuzz/README.md).
bash scripts/fuzz.sh 5
