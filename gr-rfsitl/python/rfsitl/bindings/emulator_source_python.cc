#include <gnuradio/rfsitl/emulator_source.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

void bind_emulator_source(py::module& m) {
  using gr::rfsitl::emulator_source;
  py::class_<emulator_source, gr::sync_block, gr::block, gr::basic_block,
             std::shared_ptr<emulator_source>>(
      m, "emulator_source",
      "Receive half of an rfsitl external node: joins the emulator at socket_path as node_id, "
      "outputs the node's received samples tick by tick (paces the flowgraph) and answers "
      "every tick with the samples buffered by the emulator_sink of the same node.")
      .def(py::init(&emulator_source::make), py::arg("socket_path"), py::arg("node_id"),
           py::arg("timeout_ms") = 2000, py::arg("reconnect_ms") = 20000,
           "timeout_ms: tick silence after which the node rejoins; reconnect_ms: how long to "
           "keep trying to (re)connect before the block ends the stream")
      .def("connected", &emulator_source::connected)
      .def("finished", &emulator_source::finished)
      .def("sample_rate", &emulator_source::sample_rate)
      .def("tick_samples", &emulator_source::tick_samples)
      .def("ticks", &emulator_source::ticks)
      .def("joins", &emulator_source::joins)
      .def("discontinuities", &emulator_source::discontinuities)
      .def("tx_samples_sent", &emulator_source::tx_samples_sent);
}
