#include <gnuradio/rfsitl/ubanc_framing.h>
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_ubanc_framing(py::module& m) {
  using gr::rfsitl::ubanc_framing;
  py::class_<ubanc_framing, gr::block, gr::basic_block, std::shared_ptr<ubanc_framing>>(
      m, "ubanc_framing",
      "UB-ANC net framing [src][dst][payload][\\r\\r\\n\\n] <-> packet PDUs. Ports: net_in "
      "(byte chunks from the agent) -> radio_out (PDU [src][dst][payload]); radio_in (decoded "
      "PDUs) -> net_out (framed bytes for the agent).")
      .def(py::init(&ubanc_framing::make), py::arg("node_id") = 0, py::arg("max_payload") = 2048,
           "node_id: pass decoded frames only if dst is node_id or 255 (0: pass all)")
      .def("frames_to_radio", &ubanc_framing::frames_to_radio)
      .def("frames_to_net", &ubanc_framing::frames_to_net)
      .def("framing_errors", &ubanc_framing::framing_errors)
      .def("frames_filtered", &ubanc_framing::frames_filtered);
}
