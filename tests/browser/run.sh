#!/usr/bin/env bash
# Runs the dashboard's browser test: installs playwright-core from the npm
# registry when node_modules is missing or older than package-lock.json, then
# drives the real emulator and headless Chromium (tests/browser/dashboard_test.mjs).
#
#   tests/browser/run.sh                  # uses build-dev/apps/rfsitl
#   RFSITL_BIN=build/apps/rfsitl RFSITL_ARTIFACTS=/tmp/shots tests/browser/run.sh
#
# Needs node >= 20 and Chromium (Debian: apt-get install -y chromium; or set
# CHROMIUM_PATH). Exit code: 0 pass, 1 test failure, 2 setup problem.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cd "$here"

command -v node >/dev/null || { echo "run.sh: node (>= 20) is not installed" >&2; exit 2; }
major="$(node -p 'process.versions.node.split(".")[0]')"
if (( major < 20 )); then
  echo "run.sh: node $(node --version) is too old; the test needs node >= 20" >&2
  exit 2
fi
chromium="${CHROMIUM_PATH:-/usr/bin/chromium}"
if [[ ! -x "$chromium" ]]; then
  echo "run.sh: no Chromium at $chromium: apt-get install -y chromium (or set CHROMIUM_PATH)" >&2
  exit 2
fi
bin="${RFSITL_BIN:-$here/../../build-dev/apps/rfsitl}"
if [[ ! -x "$bin" ]]; then
  echo "run.sh: no emulator at $bin: build it (cmake --build build-dev --target rfsitl) or set RFSITL_BIN" >&2
  exit 2
fi

# node_modules is current when it was installed from this very package-lock.json.
stamp="node_modules/.rfsitl-lock.sha256"
want="$(sha256sum package-lock.json | cut -d' ' -f1)"
if [[ ! -f "$stamp" || "$(cat "$stamp")" != "$want" || ! -d node_modules/playwright-core ]]; then
  echo "run.sh: installing test dependencies (npm ci)"
  npm ci --no-audit --no-fund
  echo "$want" > "$stamp"
fi

exec node dashboard_test.mjs "$@"
