/// The native part of the `rfsitl` Python package (python/rfsitl/): thin
/// conversions between Python and the C++ classes beside this file. NumPy
/// arrays are filled column by column in C++ (no Python object per number);
/// the engine runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "real_time_run.hpp"
#include "rfsitl/common/build_version.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/engine/frame_event.hpp"
#include "rfsitl/engine/node_counter_fields.hpp"
#include "rfsitl/registry/plugin_loader.hpp"
#include "rfsitl/scenario/all_components.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "virtual_run.hpp"

namespace py = pybind11;
using namespace rfsitl;

namespace {

/// One column of a table: `value(row)` for every row, in a new array.
template <typename T, typename Rows, typename Value>
py::array_t<T> column(const Rows& rows, Value value) {
  py::array_t<T> out(static_cast<py::ssize_t>(rows.size()));
  T* p = out.mutable_data();
  for (const auto& row : rows) *p++ = static_cast<T>(value(row));
  return out;
}

double or_nan(const std::optional<double>& v) {
  return v ? *v : std::nan("");
}

scenario::Scenario with_setting(const scenario::Scenario& s, const std::string& key,
                                const std::string& value) {
  scenario::Scenario out = s;
  scenario::apply_setting(out, key, value, key);
  return out;
}

// Every node's counters: (column names, N x F array), one column per field
// of kNodeCounterFields and, for a field counted by reason, one per reason.
py::tuple counters_table(python::VirtualRun& run) {
  const std::vector<engine::NodeCountersSnapshot> c = run.counters();
  std::vector<std::string> names;
  for (const auto& f : engine::kNodeCounterFields) {
    names.emplace_back(f.key);
    if (f.by_reason != nullptr) {
      for (const auto& r : engine::kLossReasons) {
        names.push_back(std::string(f.key) + "_" + std::string(r.key));
      }
    }
  }
  py::array_t<std::uint64_t> table({c.size(), names.size()});
  auto t = table.mutable_unchecked<2>();
  for (std::size_t i = 0; i < c.size(); ++i) {
    py::ssize_t j = 0;
    for (const auto& f : engine::kNodeCounterFields) {
      t(i, j++) = f.read(c[i]);
      if (f.by_reason != nullptr) {
        for (const std::uint64_t v : c[i].*(f.by_reason)) t(i, j++) = v;
      }
    }
  }
  return py::make_tuple(names, table);
}

py::dict links_table(const python::VirtualRun& run, std::size_t payload_bytes) {
  using monitor::LinkRow;
  const std::vector<LinkRow> rows = run.links(payload_bytes);
  py::dict d;
  d["tx"] = column<std::uint8_t>(rows, [](const LinkRow& r) { return r.tx; });
  d["rx"] = column<std::uint8_t>(rows, [](const LinkRow& r) { return r.rx; });
  d["distance_m"] = column<double>(rows, [](const LinkRow& r) { return or_nan(r.distance_m); });
  d["gain_db"] = column<double>(rows, [](const LinkRow& r) { return or_nan(r.gain_db); });
  d["snr_db"] = column<double>(rows, [](const LinkRow& r) { return or_nan(r.snr_db); });
  d["per"] = column<double>(rows, [](const LinkRow& r) { return or_nan(r.per); });
  return d;
}

// Events as columns; `kind` and `reason` as codes (the names: event_kinds(),
// loss_reasons()); payloads as a list of bytes.
py::dict events_table(python::VirtualRun& run) {
  using engine::FrameEvent;
  const std::vector<FrameEvent> ev = run.take_events();
  const double fs = run.scenario().timing.sample_rate_hz;
  py::dict d;
  d["time_s"] =
      column<double>(ev, [fs](const FrameEvent& e) { return static_cast<double>(e.time) / fs; });
  d["kind"] = column<std::uint8_t>(ev, [](const FrameEvent& e) { return e.kind; });
  d["node"] = column<std::uint8_t>(ev, [](const FrameEvent& e) { return e.node; });
  d["src"] = column<std::uint8_t>(ev, [](const FrameEvent& e) { return e.src; });
  d["dst"] = column<std::uint8_t>(ev, [](const FrameEvent& e) { return e.dst; });
  d["serial"] = column<std::uint32_t>(ev, [](const FrameEvent& e) { return e.serial; });
  d["length_samples"] =
      column<std::uint32_t>(ev, [](const FrameEvent& e) { return e.length_samples; });
  d["snr_db"] = column<double>(ev, [](const FrameEvent& e) { return or_nan(e.snr_db); });
  d["reason"] = column<std::int8_t>(
      ev, [](const FrameEvent& e) { return e.reason ? static_cast<int>(*e.reason) : -1; });
  d["retry"] = column<bool>(ev, [](const FrameEvent& e) { return e.retry; });
  py::list payloads(ev.size());
  for (std::size_t i = 0; i < ev.size(); ++i) {
    payloads[i] =
        py::bytes(reinterpret_cast<const char*>(ev[i].payload.data()), ev[i].payload.size());
  }
  d["payload"] = payloads;
  return d;
}

// The tap's samples as a complex64 array that owns them (no copy).
py::tuple samples_array(python::VirtualRun& run, NodeId id) {
  auto* held = new python::TapBuffer(run.take_samples(id));
  py::capsule owner(held, [](void* p) { delete static_cast<python::TapBuffer*>(p); });
  py::array_t<std::complex<float>> a(static_cast<py::ssize_t>(held->samples.size()),
                                     held->samples.data(), owner);
  const double fs = run.scenario().timing.sample_rate_hz;
  return py::make_tuple(static_cast<double>(held->first) / fs, a, held->cut);
}

py::array_t<double> local_positions(const python::VirtualRun& run) {
  const std::vector<std::optional<Ecef>> p = run.positions();
  const GeodeticPosition origin = run.scenario().channel.origin;
  py::array_t<double> out({p.size(), std::size_t{3}});
  auto o = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const LocalPosition l = p[i] ? ecef_to_local(*p[i], origin) : LocalPosition{NAN, NAN, NAN};
    o(i, 0) = l.x_m;
    o(i, 1) = l.y_m;
    o(i, 2) = l.z_m;
  }
  return out;
}

position::StateReport state_report(std::optional<std::array<double, 3>> local,
                                   std::optional<std::array<double, 3>> geodetic,
                                   std::optional<std::array<double, 3>> velocity,
                                   std::optional<std::array<double, 3>> attitude) {
  position::StateReport r;
  if (local && geodetic)
    throw std::invalid_argument("give a local or a geodetic position, not both");
  if (local) r.position = LocalPosition{(*local)[0], (*local)[1], (*local)[2]};
  if (geodetic) r.position = GeodeticPosition{(*geodetic)[0], (*geodetic)[1], (*geodetic)[2]};
  if (velocity) r.velocity = position::Velocity{(*velocity)[0], (*velocity)[1], (*velocity)[2]};
  if (attitude) r.attitude = position::Attitude{(*attitude)[0], (*attitude)[1], (*attitude)[2]};
  return r;
}

std::vector<std::string> event_kinds() {
  std::vector<std::string> out;
  for (int k = 0; k <= static_cast<int>(engine::FrameEventKind::kLost); ++k) {
    out.emplace_back(engine::frame_event_name(static_cast<engine::FrameEventKind>(k)));
  }
  return out;
}

std::vector<std::string> loss_reasons() {
  std::vector<std::string> out;
  for (const auto& r : engine::kLossReasons) out.emplace_back(r.key);
  return out;
}

}  // namespace

PYBIND11_MODULE(_rfsitl, m) {
  m.doc() = "rfsitl's engine, for the rfsitl package (import rfsitl, not this)";
  auto scenario_error =
      py::register_exception<scenario::ScenarioError>(m, "ScenarioError", PyExc_ValueError);
  py::register_exception<session::SessionError>(m, "RunError", PyExc_RuntimeError);
  // A Session's error is often the scenario's: both derive from runtime_error.
  static_cast<void>(scenario_error);

  m.def("version", [] { return std::string(build_version()); });
  m.def("load_plugins", [](const std::string& installed) {
    std::vector<std::pair<std::string, std::string>> skipped;
    for (const auto& p : registry::load_plugins(registry::plugin_folders(installed))) {
      if (!p.loaded) skipped.emplace_back(p.path, p.error);
    }
    return skipped;
  });
  m.def("components_json", [] { return scenario::all_components_json().dump(); });
  m.def("event_kinds", &event_kinds);
  m.def("loss_reasons", &loss_reasons);

  py::class_<scenario::Scenario>(m, "Scenario")
      .def_static("from_yaml", &scenario::parse_scenario, py::arg("text"), py::arg("source"))
      .def_static("load", &scenario::load_scenario_file, py::arg("path"))
      .def_static(
          "from_json",
          [](const std::string& text, const std::string& source, const std::string& base_dir) {
            return scenario::scenario_from_json(nlohmann::json::parse(text), source, base_dir);
          },
          py::arg("text"), py::arg("source"), py::arg("base_dir"))
      .def("with_setting", &with_setting, py::arg("key"), py::arg("value"))
      .def_readonly("name", &scenario::Scenario::name)
      .def_readonly("seed", &scenario::Scenario::seed)
      .def_property_readonly("node_ids",
                             [](const scenario::Scenario& s) {
                               std::vector<int> ids;
                               for (const auto& n : s.nodes) ids.push_back(n.id);
                               return ids;
                             })
      .def_property_readonly("duration_s",
                             [](const scenario::Scenario& s) { return s.timing.duration_s; })
      .def_property_readonly("sample_rate_hz",
                             [](const scenario::Scenario& s) { return s.timing.sample_rate_hz; })
      .def_property_readonly("tick_samples",
                             [](const scenario::Scenario& s) { return s.timing.tick_samples; })
      .def_property_readonly("noise_variance",
                             [](const scenario::Scenario& s) { return s.channel.noise_variance; });

  py::class_<python::VirtualRun>(m, "VirtualRun")
      .def(py::init([](const scenario::Scenario& s, bool keep_frames, bool record_events, bool taps,
                       std::size_t max_events, std::size_t max_tap_samples, const std::string& pcap,
                       const std::string& sigmf) {
             python::VirtualRunOptions o;
             o.keep_frames = keep_frames;
             o.record_events = record_events;
             o.taps = taps;
             o.max_events = max_events;
             o.max_tap_samples = max_tap_samples;
             o.pcap_path = pcap;
             o.sigmf_dir = sigmf;
             py::gil_scoped_release unlocked;
             return std::make_unique<python::VirtualRun>(s, o);
           }),
           py::arg("scenario"), py::arg("keep_frames"), py::arg("record_events"), py::arg("taps"),
           py::arg("max_events"), py::arg("max_tap_samples"), py::arg("pcap"), py::arg("sigmf"))
      .def_property_readonly("node_ids",
                             [](const python::VirtualRun& r) {
                               return std::vector<int>(r.node_ids().begin(), r.node_ids().end());
                             })
      .def_property_readonly("now_s", &python::VirtualRun::now_s)
      .def_property_readonly("tick_s", &python::VirtualRun::tick_s)
      .def_property_readonly("end_s", &python::VirtualRun::end_s)
      .def_property_readonly("finished", &python::VirtualRun::finished)
      .def_property_readonly("events_dropped", &python::VirtualRun::events_dropped)
      .def("advance", &python::VirtualRun::advance, py::arg("until_s"),
           py::call_guard<py::gil_scoped_release>())
      .def(
          "send",
          [](python::VirtualRun& r, NodeId src, NodeId dst, const py::bytes& payload) {
            const std::string b = payload;
            return r.send(src, dst, std::vector<std::uint8_t>(b.begin(), b.end()));
          },
          py::arg("src"), py::arg("dst"), py::arg("payload"))
      .def(
          "report",
          [](python::VirtualRun& r, NodeId id, std::optional<std::array<double, 3>> local,
             std::optional<std::array<double, 3>> geodetic,
             std::optional<std::array<double, 3>> velocity,
             std::optional<std::array<double, 3>> attitude) {
            r.report(id, state_report(local, geodetic, velocity, attitude));
          },
          py::arg("node"), py::arg("local") = py::none(), py::arg("geodetic") = py::none(),
          py::arg("velocity") = py::none(), py::arg("attitude") = py::none())
      .def("counters", &counters_table)
      .def("links", &links_table, py::arg("payload_bytes"))
      .def("positions", &local_positions)
      .def("take_events", &events_table)
      .def(
          "set_tap", [](python::VirtualRun& r, NodeId id, bool on) { r.set_tap(id, on); },
          py::arg("node"), py::arg("on"))
      .def("take_samples", &samples_array, py::arg("node"))
      .def("finish", [](python::VirtualRun& r) {
        std::string text;
        {
          py::gil_scoped_release unlocked;
          text = r.finish().dump();
        }
        return text;
      });

  py::class_<python::RealTimeRun>(m, "RealTimeRun")
      .def(py::init([](const scenario::Scenario& s, bool ip, bool dashboard,
                       std::optional<std::uint16_t> dashboard_port, const std::string& pcap) {
             python::RealTimeRunOptions o;
             o.ip = ip;
             o.dashboard = dashboard;
             o.dashboard_port = dashboard_port;
             o.pcap_path = pcap;
             py::gil_scoped_release unlocked;
             return std::make_unique<python::RealTimeRun>(s, o);
           }),
           py::arg("scenario"), py::arg("ip"), py::arg("dashboard"), py::arg("dashboard_port"),
           py::arg("pcap"))
      .def("start", &python::RealTimeRun::start, py::call_guard<py::gil_scoped_release>())
      .def("wait", &python::RealTimeRun::wait, py::arg("timeout_s"),
           py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("running", &python::RealTimeRun::running)
      .def_property_readonly("virtual_s",
                             [](python::RealTimeRun& r) { return r.status().virtual_s; })
      .def_property_readonly("max_lag_s",
                             [](python::RealTimeRun& r) { return r.status().max_lag_s; })
      .def_property_readonly("bind_address",
                             [](python::RealTimeRun& r) { return r.session().bind_address(); })
      .def_property_readonly(
          "net_base",
          [](python::RealTimeRun& r) { return r.session().net_ports_config().net_base; })
      .def_property_readonly("dashboard_port",
                             [](python::RealTimeRun& r) -> std::optional<int> {
                               const monitor::Dashboard* d = r.session().dashboard();
                               if (d == nullptr) return std::nullopt;
                               return d->port();
                             })
      .def("stop", [](python::RealTimeRun& r) {
        std::string text;
        {
          py::gil_scoped_release unlocked;
          text = r.stop().dump();
        }
        return text;
      });
}
