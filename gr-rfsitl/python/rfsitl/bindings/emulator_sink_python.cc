#include <gnuradio/rfsitl/emulator_sink.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

void bind_emulator_sink(py::module& m) {
  using gr::rfsitl::emulator_sink;
  py::class_<emulator_sink, gr::sync_block, gr::block, gr::basic_block,
             std::shared_ptr<emulator_sink>>(
      m, "emulator_sink",
      "Transmit half of an rfsitl external node: buffers the samples to transmit (bounded, "
      "with backpressure) for the emulator_source of the same node.")
      .def(py::init(&emulator_sink::make), py::arg("socket_path"), py::arg("node_id"),
           py::arg("len_tag_key") = "", py::arg("max_buffer_s") = 0.5,
           "len_tag_key: burst length tag (samples); a burst is released only when complete")
      .def("buffered", &emulator_sink::buffered)
      .def("samples_in", &emulator_sink::samples_in);
}
