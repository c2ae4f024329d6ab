#include "rfsitl/position/mavlink_source/vehicle_link.hpp"

#include <cmath>
#include <utility>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mavlink/requests.hpp"

namespace rfsitl::position {
namespace {

using namespace mavlink;

constexpr std::uint8_t kAutopilotComponent = 1;  // MAV_COMP_ID_AUTOPILOT1

// True when a count went from `before` to `after` across 1, 10, 100, ...: the
// moments a problem is worth a log line, so a flood costs a handful of lines.
bool crosses_power_of_ten(std::uint64_t before, std::uint64_t after) {
  for (std::uint64_t mark = 1; mark <= after; mark *= 10) {
    if (before < mark) return true;
    if (mark > after / 10) break;
  }
  return false;
}

bool names_an_autopilot(const MessagePayload& p) {
  if (std::holds_alternative<GlobalPositionInt>(p)) return true;
  const auto* h = std::get_if<Heartbeat>(&p);
  return h != nullptr && h->autopilot != kMavAutopilotInvalid && h->type != kMavTypeGcs;
}

}  // namespace

VehicleLink::VehicleLink(VehicleLinkSettings settings, std::function<void(const std::string&)> log,
                         std::function<void(const std::string&)> info)
    : settings_(settings),
      log_(std::move(log)),
      info_(std::move(info)),
      encoder_(settings.sysid != 0 ? settings.sysid : 1, settings.own_compid) {}

void VehicleLink::connected(double now_s) {
  parser_.reset();
  up_ = true;
  ++counters_.connections;
  next_heartbeat_s_ = now_s;
  asked_ = false;
  force_request_ = false;
  last_request_s_.reset();
  last_stream_s_.reset();
}

void VehicleLink::note(std::uint64_t before, std::uint64_t after, const std::string& what) {
  if (log_ && crosses_power_of_ten(before, after)) {
    log_(what + (after > 1 ? " (" + std::to_string(after) + " so far)" : ""));
  }
}

void VehicleLink::receive(std::span<const std::uint8_t> bytes, double now_s,
                          std::vector<StateReport>& out) {
  const ParserCounters before = parser_.counters();
  messages_.clear();
  parser_.feed(bytes, messages_);
  const ParserCounters& after = parser_.counters();
  note(before.bad_crc, after.bad_crc, "frame with a bad checksum dropped");
  note(before.bad_length, after.bad_length, "MAVLink 1 frame of the wrong length dropped");
  note(before.bad_incompat_flags, after.bad_incompat_flags,
       "MAVLink 2 frame with unknown incompatibility flags dropped");
  note(before.garbage_bytes, after.garbage_bytes, "bytes outside any MAVLink frame skipped");
  for (const MavlinkMessage& m : messages_) handle(m, now_s, out);
}

bool VehicleLink::from_vehicle(const FrameInfo& f, const MessagePayload& p) {
  if (!vehicle_) {
    const bool chosen = settings_.sysid != 0
                            ? f.sysid == settings_.sysid
                            : f.compid == kAutopilotComponent && names_an_autopilot(p);
    if (chosen) {
      vehicle_ = f.sysid;
      // Onboard components share their vehicle's system id.
      encoder_ = MavlinkEncoder(f.sysid, settings_.own_compid, encoder_.next_seq());
      if (info_) info_("following system " + std::to_string(f.sysid));
    }
  }
  if (!vehicle_ || f.sysid != *vehicle_) {
    const auto before = counters_.other_system++;
    note(before, counters_.other_system,
         "message from system " + std::to_string(f.sysid) + " ignored" +
             (vehicle_ ? " (following system " + std::to_string(*vehicle_) + ")"
                       : " (not an autopilot)"));
    return false;
  }
  if (f.compid != kAutopilotComponent) {
    ++counters_.other_component;  // a camera, a gimbal, a companion: not an error
    return false;
  }
  version_ = f.version;
  return true;
}

void VehicleLink::handle(const MavlinkMessage& m, double now_s, std::vector<StateReport>& out) {
  if (!from_vehicle(m.frame, m.payload)) return;
  if (const auto* g = m.get<GlobalPositionInt>()) {
    take_position(*g, now_s, out);
  } else if (const auto* a = m.get<mavlink::Attitude>()) {
    if (!std::isfinite(a->roll_rad) || !std::isfinite(a->pitch_rad) || !std::isfinite(a->yaw_rad)) {
      const auto before = counters_.bad_coordinates++;
      note(before, counters_.bad_coordinates, "ATTITUDE with a non-finite angle dropped");
      return;
    }
    StateReport r;
    r.attitude = position::Attitude{a->roll_rad, a->pitch_rad, a->yaw_rad};
    out.push_back(r);
    ++counters_.attitudes;
  } else if (const auto* ack = m.get<CommandAck>()) {
    if (ack->command == kMavCmdSetMessageInterval && ack->result != kMavResultAccepted) {
      const auto before = counters_.interval_refused++;
      note(before, counters_.interval_refused,
           "the vehicle refused SET_MESSAGE_INTERVAL (result " + std::to_string(ack->result) +
               "); asking with REQUEST_DATA_STREAM");
      legacy_ = true;
      force_request_ = true;
    }
  }
}

void VehicleLink::take_position(const GlobalPositionInt& g, double now_s,
                                std::vector<StateReport>& out) {
  last_stream_s_ = now_s;
  if (g.lat_e7 == 0 && g.lon_e7 == 0) {
    const auto before = counters_.no_fix++;
    note(before, counters_.no_fix,
         "no position fix yet (latitude = longitude = 0); the node keeps its last position");
    return;
  }
  const GeodeticPosition p{g.lat_e7 * 1e-7, g.lon_e7 * 1e-7, g.alt_mm * 1e-3};
  if (const std::string e = position_error(p); !e.empty()) {
    const auto before = counters_.bad_coordinates++;
    note(before, counters_.bad_coordinates, "GLOBAL_POSITION_INT dropped: " + e);
    return;
  }
  StateReport r;
  r.position = p;
  // NED (north, east, down) in cm/s to local east/north/up in m/s.
  r.velocity = Velocity{g.vy_cm_s * 0.01, g.vx_cm_s * 0.01, -g.vz_cm_s * 0.01};
  out.push_back(r);
  ++counters_.positions;
  last_position_s_ = now_s;
}

void VehicleLink::request_streams(double now_s, bool legacy_too, std::vector<std::uint8_t>& out) {
  const std::uint8_t sys = *vehicle_;
  if (!legacy_) {
    const std::int32_t interval = interval_us_for_rate(settings_.rate_hz);
    for (const std::uint32_t id : {GlobalPositionInt::kId, mavlink::Attitude::kId}) {
      const auto f =
          encoder_.encode(set_message_interval(sys, kAutopilotComponent, id, interval), version_);
      out.insert(out.end(), f.begin(), f.end());
      ++counters_.interval_requests;
    }
  }
  if (legacy_ || legacy_too) {
    const auto hz = static_cast<std::uint16_t>(std::lround(std::max(1.0, settings_.rate_hz)));
    for (const std::uint8_t stream : {kMavDataStreamPosition, kMavDataStreamExtra1}) {
      const auto f = encoder_.encode(
          request_data_stream(sys, kAutopilotComponent, stream, hz, true), version_);
      out.insert(out.end(), f.begin(), f.end());
      ++counters_.stream_requests;
    }
  }
  asked_ = true;
  force_request_ = false;
  last_request_s_ = now_s;
}

void VehicleLink::poll(double now_s, std::vector<std::uint8_t>& out) {
  if (!up_) return;
  if (now_s >= next_heartbeat_s_) {
    const auto f = encoder_.encode(onboard_controller_heartbeat(), version_);
    out.insert(out.end(), f.begin(), f.end());
    ++counters_.heartbeats_sent;
    next_heartbeat_s_ = now_s + kHeartbeatPeriodS;
  }
  if (!vehicle_) return;
  const bool flowing = last_stream_s_ && now_s - *last_stream_s_ <= kRequestRetryS;
  const bool retry_due = last_request_s_ && now_s - *last_request_s_ >= kRequestRetryS;
  if (!asked_ || force_request_ || (!flowing && retry_due)) {
    // A retry asks both ways: some autopilots ack the new command and ignore it.
    request_streams(now_s, asked_ && !force_request_, out);
  }
}

VehicleLinkCounters VehicleLink::counters() const {
  VehicleLinkCounters c = counters_;
  c.parser = parser_.counters();
  return c;
}

}  // namespace rfsitl::position
