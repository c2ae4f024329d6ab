/// `rfsitl mavlink-send`: stand-in vehicles for trying `rfsitl run --mavlink`
/// without an autopilot. Each vehicle is an autopilot component (system id n,
/// component 1) that sends a HEARTBEAT every second and GLOBAL_POSITION_INT at
/// a rate, flying a straight line at a constant velocity from its start. It
/// takes the same endpoint text as `--mavlink`, so the two commands pair up:
///
///   udp:HOST:PORT  the emulator listens there: vehicle n sends its datagrams
///                  to PORT + STEP (n - 1);
///   tcp:HOST:PORT  the emulator connects: vehicle n listens on
///                  PORT + STEP (n - 1) (as ArduPilot SITL does) and serves
///                  whoever connects, again after a disconnect.
///
/// What the emulator sends back (its heartbeats, stream requests) is read and
/// ignored: positions flow whether asked for or not.
#include <netdb.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <pthread.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/common/unique_fd.hpp"
#include "rfsitl/position/mavlink/encoder.hpp"
#include "rfsitl/position/mavlink_source/mavlink_endpoint.hpp"

namespace rfsitl::app {
namespace {

namespace mav = position::mavlink;

struct SendOptions {
  std::string endpoint;
  unsigned vehicles = 1;
  double lat_deg = 43.0008;
  double lon_deg = -78.7890;
  double alt_m = 10.0;
  double spacing_m = 20.0;  // vehicle n starts (n - 1) spacing east of the first
  double east_mps = 0.0, north_mps = 0.0, up_mps = 0.0;
  double rate_hz = 10.0;
  double duration_s = 0.0;  // 0: until Ctrl-C
};

/// One socket of `type` bound (listen) or connected (send) to the endpoint's
/// address. Throws std::runtime_error naming the address and the reason.
UniqueFd open_socket(const position::MavlinkEndpoint& e, bool listen) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = listen ? SOCK_STREAM : SOCK_DGRAM;
  addrinfo* found = nullptr;
  const std::string where = e.text();
  if (const int rc = ::getaddrinfo(e.host.c_str(), std::to_string(e.port).c_str(), &hints, &found);
      rc != 0) {
    throw std::runtime_error(where + ": " + ::gai_strerror(rc));
  }
  const std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> list(found, &::freeaddrinfo);
  UniqueFd fd(::socket(found->ai_family, found->ai_socktype | SOCK_CLOEXEC, 0));
  if (fd.get() < 0) throw std::runtime_error(where + ": socket: " + std::strerror(errno));
  if (listen) {
    const int on = 1;
    ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (::bind(fd.get(), found->ai_addr, found->ai_addrlen) != 0 || ::listen(fd.get(), 1) != 0) {
      throw std::runtime_error(where + ": cannot listen: " + std::strerror(errno));
    }
  } else if (::connect(fd.get(), found->ai_addr, found->ai_addrlen) != 0) {
    throw std::runtime_error(where + ": " + std::strerror(errno));
  }
  return fd;
}

/// One stand-in vehicle: its endpoint's socket and its flight.
struct Vehicle {
  std::uint8_t sysid;
  mav::MavlinkEncoder enc;
  LocalPosition start;  // east, north, up from the first vehicle's start
  UniqueFd socket;      // UDP: connected; TCP: the listener
  UniqueFd peer;        // TCP: the emulator's connection, when one is up
  bool tcp;

  /// Sends `frame` where it goes; a TCP peer that went away is dropped.
  void send(const std::vector<std::uint8_t>& frame) {
    const int fd = tcp ? peer.get() : socket.get();
    if (fd < 0) return;
    // UDP before the emulator listens: ECONNREFUSED, harmless; try again next time.
    if (::send(fd, frame.data(), frame.size(), MSG_NOSIGNAL) < 0 && tcp) peer.reset();
  }
};

int run_sender(const SendOptions& o) {
  std::string why;
  const auto endpoint = position::parse_mavlink_endpoint(o.endpoint, why);
  if (!endpoint) {
    std::fprintf(stderr, "rfsitl mavlink-send: %s\n", why.c_str());
    return 2;
  }
  const bool tcp = endpoint->transport == position::MavlinkTransport::kTcpClient;
  if (o.vehicles > 1 && endpoint->step == 0) {
    std::fprintf(stderr,
                 "rfsitl mavlink-send: --vehicles %u needs a port step (e.g. %s+1): vehicle n "
                 "uses PORT + STEP (n - 1)\n",
                 o.vehicles, o.endpoint.c_str());
    return 2;
  }
  const GeodeticPosition origin{o.lat_deg, o.lon_deg, o.alt_m};
  std::vector<Vehicle> vehicles;
  try {
    for (unsigned n = 1; n <= o.vehicles; ++n) {
      const auto mine = endpoint->for_node(static_cast<NodeId>(n));
      if (!mine) throw std::runtime_error("vehicle " + std::to_string(n) + ": port beyond 65535");
      vehicles.push_back({static_cast<std::uint8_t>(n),
                          mav::MavlinkEncoder(static_cast<std::uint8_t>(n), 1),
                          LocalPosition{o.spacing_m * (n - 1), 0.0, 0.0}, open_socket(*mine, tcp),
                          UniqueFd(), tcp});
      std::printf("rfsitl mavlink-send: vehicle %u (system %u) %s %s\n", n, n,
                  tcp ? "serving" : "sending to", mine->text().c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl mavlink-send: %s\n", e.what());
    return 2;
  }
  std::fflush(stdout);

  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const double period_s = 1.0 / o.rate_hz;
  double next_heartbeat_s = 0.0;
  std::uint64_t positions_sent = 0;
  for (std::uint64_t k = 0;; ++k) {
    const double t = static_cast<double>(k) * period_s;
    if (o.duration_s > 0 && t > o.duration_s) break;
    // Until the send time: take connections, drop what the emulator says, and
    // leave at Ctrl-C.
    for (;;) {
      const double now =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (now >= t) break;
      std::vector<pollfd> fds;
      for (const Vehicle& v : vehicles) {
        fds.push_back({v.peer.valid() ? v.peer.get() : v.socket.get(), POLLIN, 0});
      }
      const timespec no_wait{0, 0};
      if (const int sig = sigtimedwait(&signals, nullptr, &no_wait);
          sig == SIGINT || sig == SIGTERM) {
        std::printf("rfsitl mavlink-send: stopped after %llu positions\n",
                    static_cast<unsigned long long>(positions_sent));
        return 0;
      }
      const int wait_ms = std::max(1, static_cast<int>(std::min(50.0, 1e3 * (t - now))));
      if (::poll(fds.data(), fds.size(), wait_ms) <= 0) continue;
      for (std::size_t i = 0; i < vehicles.size(); ++i) {
        if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
        Vehicle& v = vehicles[i];
        if (v.tcp && !v.peer.valid()) {
          v.peer.reset(::accept4(v.socket.get(), nullptr, nullptr, SOCK_CLOEXEC));
          if (v.peer.valid()) std::printf("rfsitl mavlink-send: vehicle %u connected\n", v.sysid);
          std::fflush(stdout);
          continue;
        }
        std::uint8_t ignored[2048];
        const ssize_t n = ::recv(fds[i].fd, ignored, sizeof ignored, MSG_DONTWAIT);
        if (n == 0 && v.tcp) v.peer.reset();  // the emulator closed: serve the next one
      }
    }
    const bool heartbeat = t >= next_heartbeat_s;
    if (heartbeat) next_heartbeat_s += 1.0;
    for (Vehicle& v : vehicles) {
      if (heartbeat) {
        mav::Heartbeat h;
        h.type = mav::kMavTypeQuadrotor;
        h.autopilot = mav::kMavAutopilotArdupilotmega;
        v.send(v.enc.encode(h));
      }
      const LocalPosition at{v.start.x_m + o.east_mps * t, v.start.y_m + o.north_mps * t,
                             v.start.z_m + o.up_mps * t};
      const GeodeticPosition g = ecef_to_geodetic(local_to_ecef(at, origin));
      mav::GlobalPositionInt p;
      p.time_boot_ms = static_cast<std::uint32_t>(1e3 * t);
      p.lat_e7 = static_cast<std::int32_t>(std::lround(g.lat_deg * 1e7));
      p.lon_e7 = static_cast<std::int32_t>(std::lround(g.lon_deg * 1e7));
      p.alt_mm = static_cast<std::int32_t>(std::lround(g.alt_m * 1e3));
      p.relative_alt_mm = static_cast<std::int32_t>(std::lround(at.z_m * 1e3));
      p.vx_cm_s = static_cast<std::int16_t>(std::lround(o.north_mps * 100));
      p.vy_cm_s = static_cast<std::int16_t>(std::lround(o.east_mps * 100));
      p.vz_cm_s = static_cast<std::int16_t>(std::lround(-o.up_mps * 100));
      v.send(v.enc.encode(p));
    }
    ++positions_sent;
  }
  std::printf("rfsitl mavlink-send: done, %llu positions per vehicle\n",
              static_cast<unsigned long long>(positions_sent));
  return 0;
}

}  // namespace

std::function<int()> add_mavlink_send_command(CLI::App& parent) {
  auto o = std::make_shared<SendOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "mavlink-send",
      "Stand-in MAVLink vehicles for trying `rfsitl run --mavlink` without an autopilot: "
      "heartbeats and GLOBAL_POSITION_INT along a straight line");
  cmd->add_option("endpoint", o->endpoint,
                  "The emulator's --mavlink endpoint: udp:HOST:PORT[+STEP] (it listens; the "
                  "vehicles send there) or tcp:HOST:PORT[+STEP] (the vehicles listen; it connects)")
      ->type_name("ENDPOINT")
      ->required();
  cmd->add_option("--vehicles", o->vehicles, "Vehicles (system ids 1..N); N > 1 needs +STEP")
      ->check(CLI::Range(1U, 254U))
      ->capture_default_str();
  cmd->add_option("--lat", o->lat_deg, "Latitude of vehicle 1's start (degrees)")
      ->check(CLI::Range(-90.0, 90.0))
      ->capture_default_str();
  cmd->add_option("--lon", o->lon_deg, "Longitude of vehicle 1's start (degrees)")
      ->check(CLI::Range(-180.0, 180.0))
      ->capture_default_str();
  cmd->add_option("--alt", o->alt_m, "Altitude of the starts (m above mean sea level)")
      ->capture_default_str();
  cmd->add_option("--spacing", o->spacing_m,
                  "Vehicle n starts (n - 1) x this east of vehicle 1 (m)")
      ->capture_default_str();
  cmd->add_option("--east", o->east_mps, "Velocity east (m/s)")->capture_default_str();
  cmd->add_option("--north", o->north_mps, "Velocity north (m/s)")->capture_default_str();
  cmd->add_option("--up", o->up_mps, "Velocity up (m/s)")->capture_default_str();
  cmd->add_option("--rate", o->rate_hz, "Positions per second per vehicle (Hz)")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "Seconds to send; 0: until Ctrl-C")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  return [o] { return run_sender(*o); };
}

}  // namespace rfsitl::app
