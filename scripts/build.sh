#!/usr/bin/env bash
# Configures and builds one flavour of rfsitl, reusing the build directory.
#   scripts/build.sh release   -> build/release  (optimized; the demo and benchmarks)
#   scripts/build.sh asan      -> build/asan     (AddressSanitizer + UBSan; the tests)
set -euo pipefail
cd "$(dirname "$0")/.."
flavour="${1:-release}"
case "$flavour" in
  release) args=(-DCMAKE_BUILD_TYPE=Release -DRFSITL_BUILD_TESTS=OFF) ;;
  asan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DRFSITL_SANITIZE=ON) ;;
  *) echo "build.sh: unknown flavour '$flavour' (release or asan)" >&2; exit 2 ;;
esac
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "build/$flavour" -G Ninja "${args[@]}" "${launcher[@]}" >/dev/null
cmake --build "build/$flavour" -j "$(nproc)"
