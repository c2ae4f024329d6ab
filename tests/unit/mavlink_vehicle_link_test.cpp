// The MAVLink source's protocol logic (VehicleLink) driven byte by byte on a
// made-up clock, with the codec's encoder standing in for the vehicle (the
// codec has its own tests against a second reading of the specification).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rfsitl/position/mavlink/encoder.hpp"
#include "rfsitl/position/mavlink/parser.hpp"
#include "rfsitl/position/mavlink_source/mavlink_endpoint.hpp"
#include "rfsitl/position/mavlink_source/vehicle_link.hpp"

namespace rfsitl::position {
namespace {

using namespace mavlink;
using Bytes = std::vector<std::uint8_t>;

// ---- endpoints -------------------------------------------------------------------

TEST(MavlinkEndpoint, ParsesTransportHostPortAndStep) {
  std::string why;
  const auto tcp = parse_mavlink_endpoint("tcp:127.0.0.1:5762+10", why);
  ASSERT_TRUE(tcp) << why;
  EXPECT_EQ(tcp->transport, MavlinkTransport::kTcpClient);
  EXPECT_EQ(tcp->host, "127.0.0.1");
  EXPECT_EQ(tcp->port, 5762);
  EXPECT_EQ(tcp->step, 10);
  EXPECT_EQ(tcp->for_node(1)->port, 5762);
  EXPECT_EQ(tcp->for_node(3)->port, 5782);
  EXPECT_EQ(tcp->for_node(3)->text(), "tcp:127.0.0.1:5782");

  const auto udp = parse_mavlink_endpoint("udp:[::1]:14560", why);
  ASSERT_TRUE(udp) << why;
  EXPECT_EQ(udp->transport, MavlinkTransport::kUdpListen);
  EXPECT_EQ(udp->host, "::1");
  EXPECT_EQ(udp->step, 0);
  EXPECT_EQ(udp->for_node(9)->port, 14560);  // no step: every node the same port
  EXPECT_EQ(udp->text(), "udp:[::1]:14560");
}

TEST(MavlinkEndpoint, RefusesMalformedTextQuotingIt) {
  for (const char* bad :
       {"", "tcp:5762", "serial:/dev/ttyUSB0", "tcp:host:0", "tcp:host:70000", "tcp::5762",
        "udp:host:14560+0", "udp:host:port", "tcp:::1:5760", "tcp:[::1:5760", "tcp:host:5760+x"}) {
    std::string why;
    EXPECT_FALSE(parse_mavlink_endpoint(bad, why)) << bad;
    EXPECT_NE(why.find("'" + std::string(bad) + "'"), std::string::npos) << why;
  }
}

TEST(MavlinkEndpoint, ANodeWhosePortWouldPass65535HasNone) {
  std::string why;
  const auto e = parse_mavlink_endpoint("tcp:localhost:65000+100", why);
  ASSERT_TRUE(e);
  EXPECT_TRUE(e->for_node(6));   // 65500
  EXPECT_FALSE(e->for_node(7));  // 65600
}

// ---- the vehicle link --------------------------------------------------------------

// A vehicle: an autopilot component of system `sysid`.
struct Vehicle {
  MavlinkEncoder enc;
  MavlinkVersion version = MavlinkVersion::kV2;
  explicit Vehicle(std::uint8_t sysid, std::uint8_t compid = 1) : enc(sysid, compid) {}

  Bytes heartbeat() {
    Heartbeat h;
    h.type = kMavTypeQuadrotor;
    h.autopilot = kMavAutopilotArdupilotmega;
    return enc.encode(h, version);
  }
  Bytes position(double lat, double lon, double alt_m, std::int16_t vn = 0, std::int16_t ve = 0,
                 std::int16_t vd = 0) {
    GlobalPositionInt g;
    g.lat_e7 = static_cast<std::int32_t>(lat * 1e7);
    g.lon_e7 = static_cast<std::int32_t>(lon * 1e7);
    g.alt_mm = static_cast<std::int32_t>(alt_m * 1e3);
    g.vx_cm_s = vn;
    g.vy_cm_s = ve;
    g.vz_cm_s = vd;
    return enc.encode(g, version);
  }
  Bytes ack(std::uint16_t command, std::uint8_t result) {
    CommandAck a;
    a.command = command;
    a.result = result;
    return enc.encode(a, version);
  }
};

// What the link sent, decoded.
std::vector<MavlinkMessage> sent(const Bytes& bytes) {
  MavlinkParser p;
  std::vector<MavlinkMessage> out;
  p.feed(bytes, out);
  EXPECT_EQ(p.counters().garbage_bytes, 0U);
  EXPECT_EQ(p.counters().bad_crc, 0U);
  return out;
}

template <class T>
std::vector<T> of_type(const std::vector<MavlinkMessage>& ms) {
  std::vector<T> out;
  for (const auto& m : ms) {
    if (const T* t = m.get<T>()) out.push_back(*t);
  }
  return out;
}

struct LinkRig {
  std::vector<std::string> log;   // problems
  std::vector<std::string> info;  // the normal course
  VehicleLink link;
  std::vector<StateReport> reports;
  explicit LinkRig(VehicleLinkSettings s = {})
      : link(
            s, [this](const std::string& line) { log.push_back(line); },
            [this](const std::string& line) { info.push_back(line); }) {}

  void feed(const Bytes& b, double t) { link.receive(b, t, reports); }
  Bytes poll(double t) {
    Bytes out;
    link.poll(t, out);
    return out;
  }
};

TEST(VehicleLink, GreetsWithAnOnboardHeartbeatEverySecondFromConnection) {
  LinkRig r;
  EXPECT_TRUE(r.poll(0.0).empty());  // not connected: nothing to say
  r.link.connected(10.0);
  const auto first = sent(r.poll(10.0));
  ASSERT_EQ(first.size(), 1U);
  const auto* h = first[0].get<Heartbeat>();
  ASSERT_NE(h, nullptr);
  EXPECT_EQ(h->type, kMavTypeOnboardController);
  EXPECT_EQ(h->autopilot, kMavAutopilotInvalid);
  EXPECT_EQ(first[0].frame.compid, 191);
  EXPECT_TRUE(r.poll(10.5).empty());
  EXPECT_EQ(of_type<Heartbeat>(sent(r.poll(11.0))).size(), 1U);
  EXPECT_EQ(r.link.counters().heartbeats_sent, 2U);
}

TEST(VehicleLink, AsksTheVehicleItHeardForPositionAndAttitudeAtTheRate) {
  LinkRig r(VehicleLinkSettings{4.0, 0, 191});
  Vehicle v(7);
  r.link.connected(0.0);
  r.poll(0.0);
  EXPECT_TRUE(of_type<CommandLong>(sent(r.poll(0.1))).empty());  // no vehicle yet
  r.feed(v.heartbeat(), 0.2);
  ASSERT_EQ(r.link.vehicle(), 7);
  const auto out = sent(r.poll(0.3));
  const auto commands = of_type<CommandLong>(out);
  ASSERT_EQ(commands.size(), 2U);
  for (const auto& c : commands) {
    EXPECT_EQ(c.command, kMavCmdSetMessageInterval);
    EXPECT_EQ(c.target_system, 7);
    EXPECT_EQ(c.target_component, 1);
    EXPECT_EQ(c.param[1], 250000.0F);  // 4 Hz
  }
  EXPECT_EQ(commands[0].param[0], float(GlobalPositionInt::kId));
  EXPECT_EQ(commands[1].param[0], float(mavlink::Attitude::kId));
  EXPECT_TRUE(of_type<RequestDataStream>(out).empty());
  for (const auto& m : out) EXPECT_EQ(m.frame.sysid, 7);  // an onboard component of system 7
}

TEST(VehicleLink, ReportsPositionsAndNedVelocityAsEastNorthUp) {
  LinkRig r;
  Vehicle v(1);
  r.link.connected(0.0);
  r.feed(v.position(43.0012345, -78.7891234, 120.5, /*vn=*/300, /*ve=*/-150, /*vd=*/-50), 1.0);
  ASSERT_EQ(r.reports.size(), 1U);
  const auto& g = std::get<GeodeticPosition>(*r.reports[0].position);
  EXPECT_NEAR(g.lat_deg, 43.0012345, 1e-7);
  EXPECT_NEAR(g.lon_deg, -78.7891234, 1e-7);
  EXPECT_NEAR(g.alt_m, 120.5, 1e-3);
  ASSERT_TRUE(r.reports[0].velocity);
  EXPECT_DOUBLE_EQ(r.reports[0].velocity->vx_mps, -1.5);  // east
  EXPECT_DOUBLE_EQ(r.reports[0].velocity->vy_mps, 3.0);   // north
  EXPECT_DOUBLE_EQ(r.reports[0].velocity->vz_mps, 0.5);   // up
  EXPECT_EQ(r.link.last_position_s(), 1.0);
}

TEST(VehicleLink, ZeroFixReportsAreCountedNotPassedOn) {
  LinkRig r;
  Vehicle v(1);
  r.link.connected(0.0);
  for (int i = 0; i < 30; ++i) r.feed(v.position(0.0, 0.0, 0.0), 0.1 * i);
  EXPECT_TRUE(r.reports.empty());
  EXPECT_EQ(r.link.counters().no_fix, 30U);
  EXPECT_FALSE(r.link.last_position_s());
  r.feed(v.position(43.0, -78.8, 10.0), 3.0);
  EXPECT_EQ(r.reports.size(), 1U);
  // Logged once when it began and at 10: not thirty lines.
  EXPECT_EQ(std::count_if(r.log.begin(), r.log.end(),
                          [](const auto& l) { return l.find("no position fix") == 0; }),
            2);
}

TEST(VehicleLink, ImpossibleCoordinatesAreRefusedAndTheLastGoodPositionStands) {
  LinkRig r;
  Vehicle v(1);
  r.link.connected(0.0);
  r.feed(v.position(43.0, -78.8, 10.0), 1.0);
  GlobalPositionInt bad;
  bad.lat_e7 = 950000000;  // 95 degrees north
  bad.lon_e7 = 10;
  r.feed(v.enc.encode(bad), 1.1);
  bad.lat_e7 = 10;
  bad.alt_mm = 200'000'000;  // 200 km up
  r.feed(v.enc.encode(bad), 1.2);
  EXPECT_EQ(r.reports.size(), 1U);
  EXPECT_EQ(r.link.counters().bad_coordinates, 2U);
  // The first of a kind is logged with its reason; later ones are counted (a
  // flood would otherwise flood the log) until the count reaches 10.
  EXPECT_NE(r.log.back().find("latitude 95 out of range [-90, 90]"), std::string::npos)
      << r.log.back();
  LinkRig fresh;
  fresh.link.connected(0.0);
  fresh.feed(v.enc.encode(bad), 0.0);
  EXPECT_NE(fresh.log.back().find("altitude 200000 out of range"), std::string::npos)
      << fresh.log.back();
}

TEST(VehicleLink, FollowsTheFirstVehicleAndIgnoresAFloodFromAnother) {
  LinkRig r;
  Vehicle mine(3), other(4), camera(3, 100);
  r.link.connected(0.0);
  r.feed(mine.heartbeat(), 0.0);
  for (int i = 0; i < 500; ++i) r.feed(other.position(10.0, 10.0, 10.0), 0.001 * i);
  for (int i = 0; i < 7; ++i) r.feed(camera.position(11.0, 11.0, 11.0), 0.6);
  r.feed(mine.position(43.0, -78.8, 5.0), 0.7);
  ASSERT_EQ(r.reports.size(), 1U);
  EXPECT_NEAR(std::get<GeodeticPosition>(*r.reports[0].position).lat_deg, 43.0, 1e-7);
  EXPECT_EQ(r.link.counters().other_system, 500U);
  EXPECT_EQ(r.link.counters().other_component, 7U);
  EXPECT_LE(r.log.size(), 4U);  // 1, 10, 100 of the flood
  // Following a vehicle is the normal case: information, not a problem.
  EXPECT_EQ(r.info, std::vector<std::string>{"following system 3"});
  for (const auto& line : r.log) EXPECT_NE(line.rfind("following system", 0), 0U) << line;
}

TEST(VehicleLink, AConfiguredSystemIdIsFollowedEvenWhenAnotherSpeaksFirst) {
  LinkRig r(VehicleLinkSettings{10.0, 9, 191});
  Vehicle first(2), wanted(9);
  r.link.connected(0.0);
  r.feed(first.heartbeat(), 0.0);
  r.feed(first.position(1.0, 1.0, 1.0), 0.0);
  EXPECT_FALSE(r.link.vehicle());
  r.feed(wanted.position(2.0, 2.0, 2.0), 0.1);
  EXPECT_EQ(r.link.vehicle(), 9);
  ASSERT_EQ(r.reports.size(), 1U);
  EXPECT_NEAR(std::get<GeodeticPosition>(*r.reports[0].position).lat_deg, 2.0, 1e-7);
}

TEST(VehicleLink, ARefusedIntervalCommandFallsBackToRequestDataStream) {
  LinkRig r;
  Vehicle v(1);
  r.link.connected(0.0);
  r.feed(v.heartbeat(), 0.0);
  r.poll(0.0);
  r.feed(v.ack(kMavCmdSetMessageInterval, kMavResultUnsupported), 0.1);
  const auto out = sent(r.poll(0.2));
  const auto streams = of_type<RequestDataStream>(out);
  ASSERT_EQ(streams.size(), 2U);
  EXPECT_EQ(streams[0].req_stream_id, kMavDataStreamPosition);
  EXPECT_EQ(streams[1].req_stream_id, kMavDataStreamExtra1);
  EXPECT_EQ(streams[0].req_message_rate_hz, 10);
  EXPECT_EQ(streams[0].start_stop, 1);
  EXPECT_TRUE(of_type<CommandLong>(out).empty());
  // Still nothing after the retry time: asked again, the legacy way only.
  const auto again = sent(r.poll(0.2 + VehicleLink::kRequestRetryS));
  EXPECT_EQ(of_type<RequestDataStream>(again).size(), 2U);
  EXPECT_TRUE(of_type<CommandLong>(again).empty());
  EXPECT_EQ(r.link.counters().interval_refused, 1U);
}

TEST(VehicleLink, AsksAgainUntilPositionsFlowThenStopsAndAsksAfterAReconnect) {
  LinkRig r;
  Vehicle v(1);
  r.link.connected(0.0);
  r.feed(v.heartbeat(), 0.0);
  EXPECT_EQ(of_type<CommandLong>(sent(r.poll(0.0))).size(), 2U);
  EXPECT_TRUE(of_type<CommandLong>(sent(r.poll(1.0))).empty());  // too soon
  // No position by the retry time: both ways this time (some autopilots ack
  // the command and ignore it).
  const auto retry = sent(r.poll(VehicleLink::kRequestRetryS));
  EXPECT_EQ(of_type<CommandLong>(retry).size(), 2U);
  EXPECT_EQ(of_type<RequestDataStream>(retry).size(), 2U);
  for (double t = 2.1; t < 10.0; t += 0.1) {
    r.feed(v.position(43.0, -78.8, 5.0), t);
    EXPECT_TRUE(of_type<CommandLong>(sent(r.poll(t))).empty()) << t;
  }
  const auto asked = r.link.counters().interval_requests;
  r.link.connected(20.0);  // the vehicle came back on a new connection
  r.feed(v.heartbeat(), 20.0);
  EXPECT_EQ(of_type<CommandLong>(sent(r.poll(20.0))).size(), 2U);
  EXPECT_EQ(r.link.counters().interval_requests, asked + 2);
  EXPECT_EQ(r.link.counters().connections, 2U);
}

TEST(VehicleLink, CorruptBytesAreCountedAndTheStreamRecovers) {
  LinkRig r;
  Vehicle v(1);
  r.link.connected(0.0);
  Bytes bad = v.position(43.0, -78.8, 5.0);
  bad[12] ^= 0x40;                          // a payload bit: the checksum fails
  Bytes stream = {0x00, 0x13, 0x37, 0xFE};  // garbage, and a v1 magic with nothing after it
  stream.insert(stream.end(), bad.begin(), bad.end());
  const Bytes good = v.position(43.5, -78.5, 6.0);
  stream.insert(stream.end(), good.begin(), good.end());
  for (std::size_t i = 0; i < stream.size(); ++i) r.feed({stream[i]}, 1.0);  // byte by byte
  ASSERT_EQ(r.reports.size(), 1U);
  EXPECT_NEAR(std::get<GeodeticPosition>(*r.reports[0].position).lat_deg, 43.5, 1e-7);
  const auto c = r.link.counters();
  EXPECT_GE(c.parser.bad_crc, 1U);
  EXPECT_GE(c.parser.garbage_bytes, 3U);
  EXPECT_TRUE(std::any_of(r.log.begin(), r.log.end(), [](const auto& l) {
    return l.find("bad checksum") != std::string::npos;
  }));
}

TEST(VehicleLink, AnswersAMavlink1VehicleInMavlink1) {
  LinkRig r;
  Vehicle v(5);
  v.version = MavlinkVersion::kV1;
  r.link.connected(0.0);
  r.feed(v.heartbeat(), 0.0);
  const auto out = sent(r.poll(0.0));
  ASSERT_FALSE(out.empty());
  for (const auto& m : out) EXPECT_EQ(m.frame.version, MavlinkVersion::kV1);
}

}  // namespace
}  // namespace rfsitl::position
