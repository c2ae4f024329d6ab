/// The MACs under saturation: N = 2, 4, 8, 16 senders, each always holding a
/// frame for one sink, with mac none, csma and tdma, through the emulator's own
/// code path (an Engine in virtual time, the real GMSK transceivers). Beside
/// the csma column, Bianchi's analytic DCF saturation throughput S and
/// collision probability p for the same N, contention windows, retry limit
/// and the times the engine really has (whole ticks: mac.hpp).
///
///   rfsitl_mac_saturation [--nodes 2,4,8,16] [--seconds 20] [--payload 500] [--csv FILE]
///   /usr/bin/python3 bench/plot_mac_saturation.py FILE -o PNG
///   rfsitl_mac_saturation --bounds [--phy ofdm --rate-mbps 24] [--sample-rate 2e6] [--payload
///   1514]
///
/// --bounds only prints, as CSV, two ceilings for one sender of `payload`-byte
/// frames (bench/ip_throughput.py puts them beside iperf3): the air time
/// (frames back to back) and csma's saturation throughput (Bianchi with N = 1:
/// the same T_s, and a mean backoff of cw_min / 2 slots).
///
/// The senders sit on a circle of 10 m around the sink: every one hears every
/// other (the channel is shared, carrier sense works), and all arrive at the
/// sink with the same power, so two frames that overlap both die there
/// (no capture, which Bianchi's model does not have either).
///
/// Measured, per run: goodput (payload bits delivered per second), the
/// fraction of data transmissions that collided (csma: ACK timeouts over data
/// transmissions; none and tdma: frames lost to collision over transmissions),
/// and the service time, the mean time a sender spends per frame (run time
/// over the frames it finished, delivered or given up).
///
/// Bianchi (IEEE JSAC 18(3), 2000) with a finite retry limit R: each station
/// transmits in a slot with probability tau = sum_j p^j / sum_j p^j (W_j + 1) / 2
/// (j = 0..R, W_j = min(2^j W, W_max), W = cw_min + 1), and a transmission
/// collides with p = 1 - (1 - tau)^(N - 1). Then P_tr = 1 - (1 - tau)^N,
/// P_s = N tau (1 - tau)^(N - 1) / P_tr and
///   S = P_s P_tr L / ((1 - P_tr) sigma + P_tr P_s T_s + P_tr (1 - P_s) T_c),
/// with the engine's times: sigma = the slot in ticks; T_s = the data frame's
/// ticks until its receiver decodes it, SIFS, the ACK's ticks, DIFS; T_c = the
/// data frame's ticks and DIFS (what the stations not involved wait).
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/registry/mac_registry.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/session.hpp"

namespace {

using namespace rfsitl;

double g_fs = 1e6;                    // the runs use 1 Msps; --bounds may set another rate
constexpr std::uint32_t kTick = 250;  // the scenario default

struct Result {
  double goodput_kbps = 0.0;
  double collided = 0.0;  // fraction of data transmissions
  double service_ms = 0.0;
  std::uint64_t transmissions = 0;
};

scenario::Scenario saturated(const std::string& mac, std::size_t senders, double seconds,
                             std::size_t payload, double frame_s) {
  scenario::Scenario s;
  s.name = "mac-saturation";
  s.seed = 11;
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.timing.sample_rate_hz = g_fs;
  s.timing.tick_samples = kTick;
  s.timing.duration_s = seconds;
  s.engine.stats_interval_s = 0.0;
  s.channel.noise_variance = 1e-12;
  s.mac.type = mac;
  s.mac.settings = mac::find_mac(mac)->info.defaults();
  if (mac == "tdma") {
    // One slot holds one frame and its guard, and there are as many slots as
    // senders (the sink, node index 0, shares slot 0 with the last sender and
    // never sends): TDMA's best case.
    s.mac.settings.set("slot_ms", std::ceil((frame_s * 1e3 + 0.5) * 4.0) / 4.0);
    s.mac.settings.set("slots", std::uint64_t{senders});
  }
  scenario::NodeConfig sink;
  sink.id = 1;
  sink.initial_position = Position{LocalPosition{0, 0, 10}};
  s.nodes.push_back(sink);
  for (std::size_t k = 0; k < senders; ++k) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(senders);
    scenario::NodeConfig n;
    n.id = static_cast<NodeId>(k + 2);
    n.initial_position = Position{LocalPosition{10.0 * std::cos(a), 10.0 * std::sin(a), 10}};
    s.nodes.push_back(n);
    // Twice as many frames as the channel could carry: never idle for want of one.
    scenario::TrafficItem t;
    t.at_s = 0.001;
    t.src = n.id;
    t.dst = 1;
    t.size_bytes = payload;
    t.interval_s = frame_s / 2.0;
    t.repeat = static_cast<unsigned>(seconds / t.interval_s);
    s.traffic.push_back(t);
  }
  return s;
}

Result run(const scenario::Scenario& s, std::size_t payload) {
  const std::vector<engine::NodeCountersSnapshot> counters = session::run_portless(s).counters;
  Result r;
  std::uint64_t delivered = 0;
  std::uint64_t collided = 0;
  double service_sum = 0.0;
  for (std::size_t i = 1; i < counters.size(); ++i) {
    const auto& c = counters[i];
    delivered += c.delivered;
    r.transmissions += c.transmitted;
    collided += s.mac.type == "csma"
                    ? c.mac.ack_timeouts
                    : c.lost[static_cast<std::size_t>(engine::LossReason::kCollision)];
    const std::uint64_t finished = c.delivered + c.lost_total();
    if (finished > 0) service_sum += s.timing.duration_s * 1e3 / static_cast<double>(finished);
  }
  r.goodput_kbps = static_cast<double>(delivered * payload * 8) / s.timing.duration_s / 1e3;
  r.collided = r.transmissions > 0
                   ? static_cast<double>(collided) / static_cast<double>(r.transmissions)
                   : 0.0;
  r.service_ms = service_sum / static_cast<double>(counters.size() - 1);
  return r;
}

struct Bianchi {
  double tau = 0.0;
  double p = 0.0;
  double goodput_kbps = 0.0;
};

/// Ticks, rounded up, of `us` microseconds (at least one): the MACs' rule.
std::size_t ticks_of_us(double us) {
  return std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(us * 1e-6 * g_fs / kTick - 1e-9)));
}

Bianchi bianchi(std::size_t n, std::size_t payload, const phy::Transceiver& radio) {
  const config::Settings d = mac::find_mac("csma")->info.defaults();
  const double w = static_cast<double>(d.get<std::uint64_t>("cw_min")) + 1.0;
  const double w_max = static_cast<double>(d.get<std::uint64_t>("cw_max")) + 1.0;
  const auto retries = d.get<std::uint64_t>("retry_limit");
  const std::size_t slot = ticks_of_us(d.get<double>("slot_us"));
  const std::size_t sifs = ticks_of_us(d.get<double>("sifs_us"));
  const std::size_t difs = sifs + 2 * slot;
  const std::size_t data = radio.frame_samples(1 + 2 + payload);  // kind, sequence, payload
  const std::size_t ack = radio.frame_samples(1 + 3);
  const std::size_t lat = radio.rx_latency_samples();
  const double t_s =
      static_cast<double>((data - 1 + lat) / kTick + sifs + (ack + kTick - 1) / kTick + difs);
  const double t_c = static_cast<double>((data + kTick - 1) / kTick + difs);
  const auto tau_of = [&](double p) {
    double num = 0.0;
    double den = 0.0;
    for (std::uint64_t j = 0; j <= retries; ++j) {
      const double pj = std::pow(p, static_cast<double>(j));
      num += pj;
      den += pj * (std::min(std::pow(2.0, static_cast<double>(j)) * w, w_max) + 1.0) / 2.0;
    }
    return num / den;
  };
  // p - (1 - (1 - tau(p))^(n-1)) rises from negative at p = 0 to positive at 1.
  double lo = 0.0;
  double hi = n > 1 ? 1.0 : 0.0;  // alone, nothing collides
  for (int k = 0; k < 100; ++k) {
    const double mid = (lo + hi) / 2.0;
    const double f = mid - (1.0 - std::pow(1.0 - tau_of(mid), static_cast<double>(n - 1)));
    (f < 0.0 ? lo : hi) = mid;
  }
  Bianchi b;
  b.p = (lo + hi) / 2.0;
  b.tau = tau_of(b.p);
  const double p_tr = 1.0 - std::pow(1.0 - b.tau, static_cast<double>(n));
  const double p_s =
      static_cast<double>(n) * b.tau * std::pow(1.0 - b.tau, static_cast<double>(n - 1)) / p_tr;
  const double tick_s = kTick / g_fs;
  const double mean_slot_s =
      ((1.0 - p_tr) * static_cast<double>(slot) + p_tr * p_s * t_s + p_tr * (1.0 - p_s) * t_c) *
      tick_s;
  b.goodput_kbps = p_s * p_tr * static_cast<double>(payload * 8) / mean_slot_s / 1e3;
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The MACs under saturation, beside Bianchi's DCF model"};
  std::vector<std::size_t> nodes = {2, 4, 8, 16};
  double seconds = 20.0;
  std::size_t payload = 500;
  std::string csv;
  app.add_option("--nodes", nodes, "Numbers of senders")->delimiter(',')->capture_default_str();
  app.add_option("--seconds", seconds, "Virtual seconds per run")->capture_default_str();
  app.add_option("--payload", payload, "Payload bytes per frame")->capture_default_str();
  app.add_option("--csv", csv, "Also write the table as CSV");
  bool bounds = false;
  std::string type = "gmsk";
  unsigned rate_mbps = 6;
  app.add_flag("--bounds", bounds, "Only print one sender's air-time and csma ceilings (CSV)");
  app.add_option("--phy", type, "--bounds: transceiver type")->capture_default_str();
  app.add_option("--rate-mbps", rate_mbps, "--bounds, ofdm: 802.11 rate")->capture_default_str();
  app.add_option("--sample-rate", g_fs, "--bounds: sample rate fs in Hz")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  if (bounds) {
    auto choice = scenario::PhyChoice::of(type);
    if (type == "ofdm") choice = choice.with("rate_mbps", rate_mbps);
    const auto r = phy::make_transceiver(choice.type, choice.settings);
    const double air_s = static_cast<double>(r->frame_samples(1 + 2 + payload)) / g_fs;
    std::printf("phy,rate_mbps,sample_rate_hz,payload_bytes,air_kbps,csma_kbps\n");
    std::printf("%s,%u,%.0f,%zu,%.2f,%.2f\n", type.c_str(), type == "ofdm" ? rate_mbps : 0, g_fs,
                payload, static_cast<double>(payload * 8) / air_s / 1e3,
                bianchi(1, payload, *r).goodput_kbps);
    return 0;
  }
  const auto radio = phy::make_transceiver("gmsk");
  const double frame_s = static_cast<double>(radio->frame_samples(1 + 2 + payload)) / g_fs;
  const double air_kbps = static_cast<double>(payload * 8) / frame_s / 1e3;
  std::printf(
      "GMSK at %.0f Msps, %zu-byte payloads: %.2f ms on the air, %.1f kbit/s if back to "
      "back; %g virtual seconds per run\n\n",
      g_fs / 1e6, payload, frame_s * 1e3, air_kbps, seconds);
  std::printf(
      "| N | none kbit/s | none coll. | tdma kbit/s | csma kbit/s | Bianchi S | S err | "
      "csma p | Bianchi p | p err | csma service ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    out << "n,none_kbps,none_collided,tdma_kbps,csma_kbps,bianchi_kbps,csma_p,bianchi_p,"
           "csma_service_ms,none_service_ms,tdma_service_ms\n";
  }
  for (const std::size_t n : nodes) {
    const Result none = run(saturated("none", n, seconds, payload, frame_s), payload);
    const Result tdma = run(saturated("tdma", n, seconds, payload, frame_s), payload);
    const Result csma = run(saturated("csma", n, seconds, payload, frame_s), payload);
    const Bianchi b = bianchi(n, payload, *radio);
    std::printf(
        "| %zu | %.1f | %.2f | %.1f | %.1f | %.1f | %+.1f %% | %.3f | %.3f | %+.1f %% | %.1f |\n",
        n, none.goodput_kbps, none.collided, tdma.goodput_kbps, csma.goodput_kbps, b.goodput_kbps,
        100.0 * (csma.goodput_kbps / b.goodput_kbps - 1.0), csma.collided, b.p,
        100.0 * (csma.collided / b.p - 1.0), csma.service_ms);
    std::fflush(stdout);
    if (out) {
      out << n << ',' << none.goodput_kbps << ',' << none.collided << ',' << tdma.goodput_kbps
          << ',' << csma.goodput_kbps << ',' << b.goodput_kbps << ',' << csma.collided << ',' << b.p
          << ',' << csma.service_ms << ',' << none.service_ms << ',' << tdma.service_ms << '\n';
    }
  }
  return 0;
}
