#include "rfsitl/position/mavlink_source/mavlink_source.hpp"

namespace rfsitl::position {

const config::Fields<MavlinkSourceSettings>& mavlink_source_settings() {
  using S = MavlinkSourceSettings;
  static const auto f =
      config::Fields<S>()
          .text("endpoint", &S::endpoint,
                "tcp:HOST:PORT (connect) or udp:HOST:PORT (listen); +STEP: node n uses "
                "PORT + STEP (n - 1)")
          .real("rate_hz", &S::rate_hz, "Hz", {0.0, 100.0, true},
                "GLOBAL_POSITION_INT and ATTITUDE rate asked of the vehicle")
          .integer("sysid", &S::sysid, "", 0, 255,
                   "the vehicle's MAVLink system id; 0: the first vehicle heard")
          .real("stale_after_s", &S::stale_after_s, "s", {0.0, 3600.0, true},
                "without a position this long the node is shown stale (it keeps its last)")
          .rule([](const S& s) {
            std::string why;
            if (s.endpoint.empty()) {
              throw config::SettingError("endpoint",
                                         "is required (tcp:HOST:PORT or udp:HOST:PORT)");
            }
            if (!parse_mavlink_endpoint(s.endpoint, why))
              throw config::SettingError("endpoint", why);
          });
  return f;
}

}  // namespace rfsitl::position
