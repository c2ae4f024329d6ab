#!/usr/bin/env bash
# Builds and installs gr-rfsitl, the GNU Radio 3.10 blocks for rfsitl external
# nodes, into a prefix (default /usr/local) so that
#   /usr/bin/python3 -c "from gnuradio import rfsitl"
# works from anywhere. Idempotent: when the installed module is newer than
# every source it depends on, it returns at once.
#
#   scripts/build_gr.sh            build + install if anything changed
#   scripts/build_gr.sh --test     ... then run the module's QA tests (ctest)
#   scripts/build_gr.sh --force    rebuild and reinstall regardless
#
# Needs Debian 12's gnuradio-dev (which brings pybind11-dev and python3-dev),
# nlohmann-json3-dev, cmake and a C++20 compiler; ninja and ccache are used
# when present. Environment: RFSITL_GR_PREFIX (install prefix, default
# /usr/local), RFSITL_GR_BUILD_DIR (default build/gr-rfsitl).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"

run_tests=0
force=0
for arg in "$@"; do
  case "$arg" in
    --test) run_tests=1 ;;
    --force) force=1 ;;
    -h | --help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "build_gr.sh: unknown argument '$arg' (--test, --force)" >&2; exit 2 ;;
  esac
done

prefix="${RFSITL_GR_PREFIX:-/usr/local}"
build_dir="${RFSITL_GR_BUILD_DIR:-$root/build/gr-rfsitl}"
# GNU Radio's Python bindings exist only for Debian's interpreter; a pyenv or
# venv python3 earlier on PATH must not be picked up anywhere below. An
# inherited PYTHONPATH (e.g. a build tree) would hide what is installed.
py=/usr/bin/python3
unset PYTHONPATH

missing=()
for p in gnuradio-dev pybind11-dev python3-dev nlohmann-json3-dev cmake; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "build_gr.sh: missing Debian packages: ${missing[*]}" >&2
  echo "  apt-get install ${missing[*]}" >&2
  exit 1
fi

# Everything the installed module is built from.
sources=(gr-rfsitl src/external/client include/rfsitl/external/client include/rfsitl/common
         scripts/build_gr.sh)

# Where the installed package lives, found the way the interpreter finds it
# (without importing the module itself, which may be stale or absent).
installed_dir() {
  "$py" - <<'EOF' 2>/dev/null
import importlib.util, os
spec = importlib.util.find_spec("gnuradio.rfsitl")
if spec and spec.origin:
    print(os.path.dirname(spec.origin))
EOF
}

stamp_name=.rfsitl_build_stamp
if [ "$force" -eq 0 ] && [ "$run_tests" -eq 0 ]; then
  dir="$(cd / && installed_dir)"
  if [ -n "$dir" ] && [ -f "$dir/$stamp_name" ] &&
     [ -z "$(find "${sources[@]}" -type f -newer "$dir/$stamp_name" -not -path '*__pycache__*' \
             -print -quit)" ]; then
    echo "build_gr.sh: gr-rfsitl in $dir is up to date"
    exit 0
  fi
fi

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ -f "$build_dir/CMakeCache.txt" ] && ! grep -q "^CMAKE_INSTALL_PREFIX:PATH=$prefix\$" \
     "$build_dir/CMakeCache.txt"; then
  rm -rf "$build_dir"  # configured for another prefix: GR_PYTHON_DIR depends on it
fi
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S gr-rfsitl -B "$build_dir" "${generator[@]}" "${launcher[@]}" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" \
    -DPYTHON_EXECUTABLE="$py" -DRFSITL_GR_WERROR=ON >/dev/null
fi
cmake --build "$build_dir" -j "$(nproc)"
installed="$(cmake --install "$build_dir")"
grep -v "Up-to-date" <<<"$installed" || true
# The Python module finds libgnuradio-rfsitl through its RPATH; refreshing the
# linker cache also serves C++ users linking against the library.
command -v ldconfig >/dev/null && ldconfig 2>/dev/null || true

# The proof that matters: a fresh Debian interpreter, any directory, no PYTHONPATH.
if ! (cd / && "$py" -c "from gnuradio import rfsitl; rfsitl.ubanc_framing()"); then
  echo "build_gr.sh: installed, but '$py -c \"from gnuradio import rfsitl\"' fails" >&2
  echo "  (is $prefix's dist-packages on that interpreter's sys.path?)" >&2
  exit 1
fi
dir="$(cd / && installed_dir)"
touch "$dir/$stamp_name"
echo "build_gr.sh: gr-rfsitl installed in $prefix (python package $dir)"

if [ "$run_tests" -eq 1 ]; then
  (cd "$build_dir" && ctest --output-on-failure --timeout 180)
fi
