#!/usr/bin/env bash
# Installs everything rfsitl needs from Debian 12's packages, then builds and
# installs our GNU Radio blocks. Idempotent: when every package is present and
# the blocks are up to date it returns at once without touching apt.
#   bash scripts/setup.sh          everything: the tests, GNU Radio, SoapySDR, MPI, ...
#   bash scripts/setup.sh --demo   only what the program and the demo need
set -euo pipefail

# What building the program and running the demo (scripts/demo.sh) need: a
# fifth of the full list's download, and no GNU Radio blocks to build.
DEMO_PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config
  libliquid-dev libfec-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  libboost-dev libbenchmark-dev python3 python3-matplotlib python3-yaml
)
if [ "${1:-}" = "--demo" ]; then
  exec bash "$(dirname "$0")/apt_install.sh" setup "${DEMO_PACKAGES[@]}"
fi

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config clang-format
  libliquid-dev libfec-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  libboost-dev libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-matplotlib python3-yaml
  # the Python module (python/rfsitl/): tables as DataFrames, Student t for the
  # campaigns' plots, and its notebook run headless in the tests (nbconvert, a kernel)
  python3-pandas python3-scipy jupyter-nbconvert python3-ipykernel
  # GNU Radio 3.10 and what our out-of-tree blocks (gr-rfsitl/) build with
  gnuradio gnuradio-dev pybind11-dev python3-dev
  # traces: libpcap to read pcapng back in tests, tshark to check Wireshark's view
  libpcap-dev tshark
  # the dashboard's browser test: Debian's Chromium driven by playwright-core (npm)
  chromium nodejs
  # IP on every node (--ip): namespaces (iproute2) and the stock tools the tests run in them
  iproute2 iputils-ping babeld
  # bench/ip_throughput.py: TCP and UDP goodput between two IP nodes
  iperf3
  # bench/thread_tuning.sh: a competing load beside the engine
  stress-ng
  # the SoapySDR module (driver=rfsitl, src/soapy/) and its test: headers, SoapySDRUtil, python
  libsoapysdr-dev soapysdr-tools python3-soapysdr
  # distributed runs (mpirun -n K rfsitl run ...): Open MPI, its headers and launcher
  libopenmpi-dev openmpi-bin
  # SoapyRemote and its test (test_soapy_remote.py): the server, the client
  # module, and the Avahi daemon without which Debian's server does not run
  soapyremote-server soapysdr-module-remote avahi-daemon
)
# Debian packages npm separately from nodejs; other nodejs builds bring their own.
command -v npm >/dev/null 2>&1 || PACKAGES+=(npm)

bash "$(dirname "$0")/apt_install.sh" setup "${PACKAGES[@]}"
# Our GNU Radio blocks (gr-rfsitl/), installed into /usr/local so that any
# flowgraph can use them; returns at once when they are up to date.
bash "$(dirname "$0")/build_gr.sh"
