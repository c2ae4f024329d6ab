#!/usr/bin/env bash
# Builds rfsitl's Debian packages (cmake/rfsitl_package.cmake) with CPack:
#   scripts/package.sh [OUTPUT_DIR]     (default build/package/packages)
# then, as root:  apt install ./OUTPUT_DIR/*.deb   (or only the ones wanted:
# rfsitl_*.deb is the program; librfsitl-dev_*, soapysdr*-module-rfsitl_*).
# Remove with:    apt purge rfsitl librfsitl-dev 'soapysdr*-module-rfsitl'
# Needs dpkg-dev (dpkg-shlibdeps) besides what scripts/build.sh needs.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/package/packages}"
bash scripts/build.sh package
mkdir -p "$out"
out="$(cd "$out" && pwd)"
rm -f "$out"/*.deb
(cd build/package && cpack -G DEB -B "$out" >/dev/null)
rm -rf "$out/_CPack_Packages"
ls "$out"/*.deb
