// Hand-written pybind11 bindings for gr-rfsitl (no bindtool: the interfaces
// are small and stable).
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_emulator_source(py::module& m);
void bind_emulator_sink(py::module& m);
void bind_ubanc_framing(py::module& m);

PYBIND11_MODULE(rfsitl_python, m) {
  m.doc() = "rfsitl: GNU Radio blocks for external nodes of the rfsitl RF channel emulator";
  // The block base classes (gr::sync_block, ...) are registered by
  // gnuradio.gr's own bindings; ours derive from them.
  py::module::import("gnuradio.gr");
  bind_emulator_source(m);
  bind_emulator_sink(m);
  bind_ubanc_framing(m);
}
