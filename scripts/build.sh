#!/usr/bin/env bash
# Configures and builds one flavour of rfsitl, reusing the build directory.
#   scripts/build.sh release   -> build/release  (optimized; the demo and benchmarks)
#   scripts/build.sh asan      -> build/asan     (AddressSanitizer + UBSan; the tests)
#   scripts/build.sh tsan      -> build/tsan     (ThreadSanitizer; scripts/test_tsan.sh)
#   scripts/build.sh package   -> build/package  (release for the prefix /usr: scripts/package.sh)
# Further arguments name the targets to build (default: all of them).
set -euo pipefail
cd "$(dirname "$0")/.."
flavour="${1:-release}"
shift || true
case "$flavour" in
  release) args=(-DCMAKE_BUILD_TYPE=Release -DRFSITL_BUILD_TESTS=OFF) ;;
  asan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DRFSITL_SANITIZE=ON) ;;
  # The release flags (ccache shares release's objects) for the prefix the
  # Debian packages install into.
  package) args=(-DCMAKE_BUILD_TYPE=Release -DRFSITL_BUILD_TESTS=OFF -DRFSITL_BUILD_BENCH=OFF
                 -DCMAKE_INSTALL_PREFIX=/usr -DRFSITL_BUILD_GR=ON) ;;
  # ThreadSanitizer cannot be combined with ASan, hence a tree of its own. GCC 12
  # warns (-Wtsan) that it does not model std::atomic_thread_fence; the one fence
  # (NodeCounters::snapshot) only orders loads of atomics, which TSan checks
  # access by access anyway, so that warning is not an error here.
  tsan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DRFSITL_SANITIZE=OFF -DRFSITL_BUILD_BENCH=OFF
              "-DCMAKE_CXX_FLAGS=-fsanitize=thread -fno-omit-frame-pointer -Wno-tsan"
              -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread) ;;
  *) echo "build.sh: unknown flavour '$flavour' (release, asan, tsan or package)" >&2; exit 2 ;;
esac
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# ccache sees paths relative to the checkout's parent folder and leaves the
# build folder's path out of its hash, so that every checkout of the project
# on this machine (a worktree, CI's copy in /tmp) shares one cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
cmake -S . -B "build/$flavour" -G Ninja "${args[@]}" "${launcher[@]}" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "build/$flavour" -j "$(nproc)" "${targets[@]}"
