/// The MAVLink position source's protocol logic (VehicleLink) on an arbitrary
/// vehicle: whatever bytes arrive, in whatever cuts and at whatever times,
///  - every report passed on is a position within the limits every input
///    accepts (never 0 N 0 E, the no-fix marker), a finite velocity, or a
///    finite attitude;
///  - the counters add up: positions reported == counters().positions, the same
///    for attitudes;
///  - everything the link sends is well-formed MAVLink (parses with no garbage
///    and no bad checksum) from its own component, and it never sends more than
///    a heartbeat and four requests per poll.
///
/// Input: [settings byte][then chunks: [len][dt][bytes...]] where len is the
/// chunk's size and dt (tenths of a second) advances the clock before it.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_check.hpp"
#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mavlink/parser.hpp"
#include "rfsitl/position/mavlink_source/vehicle_link.hpp"

namespace pos = rfsitl::position;
namespace mav = rfsitl::position::mavlink;

namespace {

void check_sent(const std::vector<std::uint8_t>& bytes) {
  mav::MavlinkParser p;
  std::vector<mav::MavlinkMessage> out;
  p.feed(bytes, out);
  FUZZ_CHECK(p.counters().garbage_bytes == 0 && p.counters().bad_crc == 0 && p.buffered() == 0,
             "the link sent a malformed stream (%zu bytes)", bytes.size());
  FUZZ_CHECK(out.size() <= 5, "%zu frames in one poll", out.size());
  for (const auto& m : out)
    FUZZ_CHECK(m.frame.compid == 191, "sent as component %u", m.frame.compid);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  pos::VehicleLinkSettings s;
  s.sysid = (data[0] & 1) != 0 ? data[0] : 0;  // odd: a configured system id
  s.rate_hz = 1.0 + (data[0] >> 4);
  pos::VehicleLink link(s, [](const std::string& line) { FUZZ_CHECK(!line.empty(), "empty log"); });
  std::span<const std::uint8_t> in(data + 1, size - 1);
  double now = 0.0;
  link.connected(now);
  std::vector<pos::StateReport> reports;
  std::uint64_t positions = 0, attitudes = 0;
  while (in.size() >= 2) {
    const std::size_t len = std::min<std::size_t>(in[0], in.size() - 2);
    now += 0.1 * in[1];
    const std::vector<std::uint8_t> chunk(in.begin() + 2, in.begin() + 2 + static_cast<long>(len));
    in = in.subspan(2 + len);
    if (len == 0 && now > 1e4) link.connected(now);  // a reconnect now and then
    reports.clear();
    link.receive(chunk, now, reports);
    for (const auto& r : reports) {
      if (r.position) {
        ++positions;
        FUZZ_CHECK(rfsitl::position_error(*r.position).empty(), "bad position passed on");
        const auto& g = std::get<rfsitl::GeodeticPosition>(*r.position);
        FUZZ_CHECK(!(g.lat_deg == 0.0 && g.lon_deg == 0.0), "a no-fix report passed on");
      }
      if (r.velocity) {
        FUZZ_CHECK(std::isfinite(r.velocity->vx_mps) && std::isfinite(r.velocity->vy_mps) &&
                       std::isfinite(r.velocity->vz_mps),
                   "non-finite velocity");
      }
      if (r.attitude) {
        ++attitudes;
        FUZZ_CHECK(std::isfinite(r.attitude->roll_rad) && std::isfinite(r.attitude->pitch_rad) &&
                       std::isfinite(r.attitude->yaw_rad),
                   "non-finite attitude");
      }
    }
    std::vector<std::uint8_t> sent;
    link.poll(now, sent);
    check_sent(sent);
  }
  const auto c = link.counters();
  FUZZ_CHECK(c.positions == positions, "positions %llu counted, %llu reported",
             static_cast<unsigned long long>(c.positions),
             static_cast<unsigned long long>(positions));
  FUZZ_CHECK(c.attitudes == attitudes, "attitudes counted %llu, reported %llu",
             static_cast<unsigned long long>(c.attitudes),
             static_cast<unsigned long long>(attitudes));
  return 0;
}
