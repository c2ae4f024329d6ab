/// Packet error rate in Rayleigh block fading against its reference, for the
/// GMSK PHY (type gmsk) and the DSSS PHY (type dsss: Barker-11, DBPSK, one
/// sample per chip), through the emulator's own code path: an Engine in
/// virtual time with two nodes, the noise variance setting the SNR, scheduled
/// 80-byte frames, the counters at the end (as bench/per_sweep.cpp does).
///
///   rfsitl_fading_per [--frames N] [--phys gmsk,dsss] [--csv FILE] [--jobs J]
///   /usr/bin/python3 bench/plot_fading_per.py FILE -o PNG
///
/// SNR is per sample, transmit power over the noise variance in fs, as in the
/// PER sweep; in fading "mean SNR" is its mean over the fades, E|h|^2 / sigma^2
/// with E|h|^2 = 1.
///
/// What it measures, per PHY:
///  a) the AWGN curve P(s): channel.stages = [path_loss (paper, exponent 0:
///     |c| = 1 at any distance)], both nodes still, on a 0.5 dB grid from
///     PER ~1 down to PER ~1e-3;
///  b) the PER in Rayleigh block fading at mean SNRs 0..30 dB: the same chain
///     followed by the real fading stage (model rayleigh, M = 32 plane waves);
///  c) the reference PER_ref(m) = integral_0^inf P(m x) exp(-x) dx, the AWGN
///     curve averaged over the exponential distribution of |h|^2, and the
///     horizontal gaps (dB of mean SNR) between (b) and (c) at a few PER
///     levels, with a pass/fail line against 1 dB.
///
/// How the fading stage is made to give block fading. The stage's gain is a
/// fixed random field over the two ends' positions (channel/stages/fading.hpp),
/// so the receiver hops: node 2 follows waypoints (set in code), standing still
/// at point k while frame k is on the air and moving to point k + 1 between
/// frames. Points are drawn uniformly in a 40 m square (320 wavelengths at the
/// default 2.4 GHz carrier). So:
///  - within a frame the gain does not vary at all (the residual variation is
///    zero, not merely small): both ends stand still and the field depends on
///    positions only. The frame starts 15 ms after the arrival (the engine
///    updates mobility every 10 ms and the channel extrapolates a node along
///    its last velocity until the next update, so the last update of a leg may
///    overshoot for up to 10 ms) and ends at least 5 ms before the departure;
///  - between frames the fades are independent: two points are typically
///    ~20 m (160 wavelengths) apart, where the field's correlation J0(k d) is
///    below 0.03 (that of |h|^2 below 0.001); for one draw of the M waves the
///    correlation of a given pair of points has an O(1/sqrt M) residue, whose
///    sign changes from pair to pair.
/// The obvious alternative, moving slowly and steadily through the field, has
/// a Doppler f_d and thus some variation within a frame, and it matters where
/// the PER is decided at high mean SNR, in deep fades: a frame is lost not
/// only when |h| is below the threshold rho (relative to its RMS) as it
/// starts, with probability ~rho^2, but also when |h| falls through rho during
/// it, at Rice's rate sqrt(2 pi) f_d rho exp(-rho^2). For the 9 ms DSSS frame
/// at f_d = 2 Hz and 20 dB of mean SNR (rho ~ 0.08) that is up to 60% more
/// PER, 2 dB; keeping it below 0.1 dB needs f_d of a few hundredths of a Hz,
/// a coherence time of ~10 s, and frames a minute or more apart (over a
/// thousand times the slot used here). The trace stage (docs/channel_traces.md)
/// would give exact block fading too, but it replays gains instead of the
/// fading stage: it would only show that the receivers take a gain step
/// between frames as an AWGN channel at another SNR. The hops test the fading
/// stage's statistics and the receivers together.
///
/// A caveat of the fading stage that the bench exposes: one link's field,
/// sampled over a bounded region, follows Exp(1) only up to O(1/M). Two waves
/// arriving from almost the same direction (|delta| << lambda / region) stay
/// coherent over the whole region, which moves its mean power by up to 2 / M
/// (6% at M = 32). Measured with channel::fading::gain over 10^6 points of the
/// square: with the seed used here the mean of |h|^2 is 0.999 and
/// P(|h|^2 < 0.01) = 0.00975 (Exp(1): 0.00995); with seed + 2, 1.063 and 0.0091,
/// which would read as a 0.3 dB offset of the measured curve.
///
/// Since the field is a pure function (channel::fading::gain), the bench also
/// computes each frame's |h_k|^2 and the "realized" reference
/// (1/N) sum_k P(m |h_k|^2): the gap between it and the reference is the fade
/// sample's own departure from Exp(1) (finite N, finite M); the gap between it
/// and the measurement is the receivers' behaviour in fading. The same fade
/// sample (same points, same stage seed) is used at every mean SNR and for
/// both PHYs: common random numbers, so the measured curve is smooth and its
/// sampling error is shared between points (the noise seeds differ).
///
/// The reference integral, with u = 10 log10(m x) in dB: below the AWGN grid
/// P = 1 (the grid starts where every frame is lost; the integral of exp(-x)
/// up to there is taken in closed form); on the grid, log10 P is interpolated
/// linearly in u (a measured 0 inside the grid counts as half a frame's
/// worth); above the last point with errors, log10 P continues with the slope
/// of the last two such points (a waterfall gets steeper, so this errs high);
/// the bench prints which share of the reference comes from that extrapolated
/// tail (it is negligible). The integrand is summed on a 0.01 dB grid.
///
/// Gap at PER level L: the mean SNR where the measured curve crosses L (log10
/// PER interpolated linearly between the two points around it) minus where the
/// reference does; positive: the measurement needs more SNR. Its statistical
/// uncertainty is printed beside it, from the binomial spread of the PER at the
/// crossing, sqrt((1 - L) / (N L)) in ln PER, over the curve's local slope.
///
/// What it gives (defaults: 20000 frames per fading point, 5000 per AWGN point;
/// 160 s of CPU time, 143 to 163 s of wall time on two cores that a compiler
/// shared): every gap within 0.22 dB for both
/// PHYs at PER 0.3, 0.1, 0.03 and 0.01 (GMSK +0.02, +0.13, +0.09, -0.22 dB;
/// DSSS +0.04, +0.10, +0.06, -0.20 dB), of which the receivers' part (the
/// measurement against the realized reference) is within 0.14 dB: they decode
/// a frame faded to SNR s as they decode it at SNR s in AWGN. With fewer
/// frames the fade sample dominates the gap (2000 frames: -0.8 to -1.1 dB at
/// PER 0.03 and 0.01, all of it from the sample).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/channel/stages/fading.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "rfsitl/session/session.hpp"

namespace {

using namespace rfsitl;

constexpr std::size_t kPayload = 80;
constexpr double kCarrierHz = 2.4e9;  // channel::RadioSettings' default
constexpr std::uint64_t kFadeSeed = 20240607;
constexpr std::uint64_t kPointSeed = 7;
// The hop's timing (see the header comment).
constexpr double kSettleS = 0.015;  // arrival to frame start: > one mobility update
constexpr double kAfterS = 0.005;   // frame end (plus a tick) to departure
constexpr double kMoveS = 0.010;    // the leg between two points
constexpr double kSquareM = 40.0;
constexpr double kHeightM = 10.0;

struct PhyCase {
  std::string name;
  scenario::PhyChoice phy;
  double awgn_from_db;  // PER ~1 here ...
  double awgn_to_db;    // ... and ~1e-3 here (from the PER sweep's curves)
};

std::vector<PhyCase> known_phys() {
  return {{"gmsk", scenario::PhyChoice::of("gmsk"), 1.0, 9.5},
          {"dsss", scenario::PhyChoice::of("dsss"), -6.0, 1.5}};
}

scenario::StageChoice stage(const char* type) {
  return {type, channel::find_channel_stage(type)->info.defaults()};
}

channel::FadingSettings fading_settings() {
  channel::FadingSettings f;
  f.model = channel::FadingModel::kRayleigh;
  f.seed = kFadeSeed;
  return f;
}

/// path_loss (paper, exponent 0: a unit-magnitude coefficient whatever the
/// distance), then, for fading, the Rayleigh stage with its own seed, so that
/// the fades do not change with the scenario seed that draws the noise.
std::vector<scenario::StageChoice> chain(bool faded) {
  scenario::StageChoice loss = stage("path_loss");
  loss.settings.set("model", std::string("paper"));
  loss.settings.set("paper_exponent", 0.0);
  if (!faded) return {loss};
  scenario::StageChoice fade = stage("fading");
  const channel::FadingSettings f = fading_settings();
  fade.settings.set("model", std::string("rayleigh"));
  fade.settings.set("sinusoids", config::Value(std::uint64_t{f.sinusoids}));
  fade.settings.set("seed", config::Value(std::uint64_t{f.seed}));
  return {loss, fade};
}
constexpr std::size_t kFadingStagePosition = 1;  // its index in chain(true)

double frame_seconds(const scenario::PhyChoice& phy, double fs) {
  return static_cast<double>(
             phy::make_transceiver(phy.type, phy.settings)->frame_samples(kPayload)) /
         fs;
}

/// The receiver's points, one per frame: uniform in the square, seeded. (The
/// doubles come from the generator's bits directly: std's distributions are not
/// the same on every standard library.)
std::vector<LocalPosition> hop_points(std::size_t n) {
  std::mt19937_64 rng(kPointSeed);
  const auto unit = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<LocalPosition> p(n);
  for (auto& q : p) {
    const double x = (unit() - 0.5) * kSquareM;
    const double y = (unit() - 0.5) * kSquareM;
    q = LocalPosition{x, y, kHeightM};
  }
  return p;
}

const LocalPosition kTxPosition{0.0, 0.0, kHeightM};

/// |h_k|^2 of each point: the fading stage's own function, with the ends where
/// the engine has them during frame k (node indices 0 and 1).
std::vector<double> fade_powers(const std::vector<LocalPosition>& points) {
  const channel::FadingSettings f = fading_settings();
  channel::LinkEnd tx;
  tx.index = 0;
  tx.local = kTxPosition;
  std::vector<double> x;
  x.reserve(points.size());
  for (const LocalPosition& p : points) {
    channel::LinkEnd rx;
    rx.index = 1;
    rx.local = p;
    x.push_back(
        std::norm(channel::fading::gain(f, kCarrierHz, f.seed, kFadingStagePosition, tx, rx)));
  }
  return x;
}

struct Job {
  std::size_t phy = 0;
  bool faded = false;
  double snr_db = 0.0;
  unsigned frames = 0;
};

struct Outcome {
  std::uint64_t delivered = 0;
  std::uint64_t pending = 0;  // frames without an outcome at the end (must be 0)
  double wall_s = 0.0;
};

Outcome run_job(const PhyCase& pc, const Job& job, const std::vector<LocalPosition>& points) {
  const auto t0 = std::chrono::steady_clock::now();
  scenario::Scenario s;
  s.name = "fading-per";
  // The noise seed differs per point and between AWGN and fading runs.
  s.seed = static_cast<std::uint64_t>(std::llround((job.snr_db + 100.0) * 10.0)) +
           (job.faded ? 100000U : 0U);
  s.phy = pc.phy;
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.engine.threads = 1;  // the jobs run in parallel instead
  s.engine.stats_interval_s = 0.0;
  s.channel.stages = chain(job.faded);
  s.channel.noise_variance = std::pow(10.0, -job.snr_db / 10.0);
  const double frame_s = frame_seconds(pc.phy, s.timing.sample_rate_hz);
  const double tick_s = s.timing.tick_samples / s.timing.sample_rate_hz;
  s.nodes = {scenario::NodeConfig::at(1, kTxPosition),
             scenario::NodeConfig::at(2, job.faded ? points.front() : kTxPosition)};
  double slot_s = 1.5 * frame_s + 0.001;  // AWGN: as the PER sweep spaces them
  double first_s = 0.001;
  if (job.faded) {
    // Hop: arrive at point k at k * slot, stand still until slot - move, send
    // frame k at k * slot + settle.
    slot_s = std::ceil((kSettleS + frame_s + tick_s + kAfterS + kMoveS) * 1000.0) / 1000.0;
    first_s = kSettleS;
    config::Records legs;
    legs.reserve(job.frames);
    for (unsigned k = 0; k < job.frames; ++k) {
      legs.push_back(config::Record{{"t", k * slot_s},
                                    {"x", points[k].x_m},
                                    {"y", points[k].y_m},
                                    {"z", points[k].z_m},
                                    {"dwell_s", slot_s - kMoveS}});
    }
    scenario::MobilityChoice m{"waypoints",
                               position::mobility::find_mobility("waypoints")->info.defaults()};
    m.settings.set("points", std::move(legs));
    s.nodes[1].mobility = std::move(m);
  }
  s.traffic = {{first_s, 1, 2, kPayload, job.frames, slot_s}};
  s.timing.duration_s = first_s + slot_s * job.frames + 0.05;
  scenario::validate_scenario(s);
  const engine::NodeCountersSnapshot c = session::run_portless(std::move(s)).counters[0];
  return {c.delivered, c.pending(),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

/// The AWGN curve as a function of SNR in dB (see the header comment).
class AwgnCurve {
 public:
  struct Point {
    double snr_db;
    double per;
    unsigned frames;
  };

  explicit AwgnCurve(std::vector<Point> measured) : pts_(std::move(measured)) {
    std::sort(pts_.begin(), pts_.end(),
              [](const Point& a, const Point& b) { return a.snr_db < b.snr_db; });
    for (std::size_t i = 0; i < pts_.size(); ++i) {
      if (pts_[i].per > 0.0) last_ = i;
    }
    for (std::size_t i = 0; i <= last_; ++i) {
      lg_.push_back(std::log10(std::max(pts_[i].per, 0.5 / pts_[i].frames)));
    }
    if (last_ >= 1) {
      slope_ = (lg_[last_] - lg_[last_ - 1]) / (pts_[last_].snr_db - pts_[last_ - 1].snr_db);
    }
  }

  double first_db() const { return pts_.front().snr_db; }
  double last_with_errors_db() const { return pts_[last_].snr_db; }
  const std::vector<Point>& points() const { return pts_; }

  /// P(u), u in dB.
  double operator()(double u) const {
    if (u <= pts_.front().snr_db) return 1.0;
    if (u >= pts_[last_].snr_db) {
      // No errors anywhere, or a slope that does not fall: nothing above.
      if (pts_[last_].per <= 0.0 || slope_ >= 0.0) return 0.0;
      return std::pow(10.0, lg_[last_] + slope_ * (u - pts_[last_].snr_db));
    }
    const auto it = std::upper_bound(pts_.begin(), pts_.begin() + static_cast<long>(last_) + 1, u,
                                     [](double v, const Point& p) { return v < p.snr_db; });
    const std::size_t i = static_cast<std::size_t>(it - pts_.begin()) - 1;
    const double w = (u - pts_[i].snr_db) / (pts_[i + 1].snr_db - pts_[i].snr_db);
    return std::min(1.0, std::pow(10.0, lg_[i] + w * (lg_[i + 1] - lg_[i])));
  }

  /// integral_0^inf P(m x) exp(-x) dx at mean SNR m (dB); `tail` gets the part
  /// from above the last measured point with errors.
  double rayleigh_average(double mean_db, double* tail = nullptr) const {
    constexpr double kDu = 0.01;
    const double ln10_10 = std::log(10.0) / 10.0;
    const double x_lo = std::pow(10.0, (first_db() - mean_db) / 10.0);
    double sum = -std::expm1(-x_lo);  // P = 1 below the grid: integral of exp(-x)
    double above = 0.0;
    // Midpoint rule in u; exp(-x) x vanishes long before x = 60.
    const double u_end = mean_db + 10.0 * std::log10(60.0);
    for (double u = first_db() + 0.5 * kDu; u < u_end; u += kDu) {
      const double x = std::pow(10.0, (u - mean_db) / 10.0);
      const double p = (*this)(u);
      if (p <= 0.0) break;
      const double term = p * std::exp(-x) * x * ln10_10 * kDu;
      sum += term;
      if (u > last_with_errors_db()) above += term;
    }
    if (tail != nullptr) *tail = above;
    return sum;
  }

  /// (1/N) sum_k P(m x_k) over the fade sample.
  double realized_average(double mean_db, const std::vector<double>& x) const {
    double sum = 0.0;
    for (const double xk : x) sum += (*this)(mean_db + 10.0 * std::log10(std::max(xk, 1e-30)));
    return sum / static_cast<double>(x.size());
  }

 private:
  std::vector<Point> pts_;
  std::vector<double> lg_;
  std::size_t last_ = 0;
  double slope_ = 0.0;
};

/// Where a decreasing curve given by points first crosses `level`, log10 PER
/// interpolated linearly; nullopt when it does not.
std::optional<double> crossing(const std::vector<std::pair<double, double>>& curve, double level) {
  for (std::size_t i = 0; i + 1 < curve.size(); ++i) {
    const auto [s0, p0] = curve[i];
    const auto [s1, p1] = curve[i + 1];
    if (p0 >= level && p1 < level && p1 > 0.0) {
      const double l0 = std::log10(p0), l1 = std::log10(p1), lt = std::log10(level);
      return s0 + (s1 - s0) * (l0 - lt) / (l0 - l1);
    }
  }
  return std::nullopt;
}

/// d ln PER / d SNR_dB of a points curve at the segment that crosses `level`.
double log_slope_at(const std::vector<std::pair<double, double>>& curve, double level) {
  for (std::size_t i = 0; i + 1 < curve.size(); ++i) {
    const auto [s0, p0] = curve[i];
    const auto [s1, p1] = curve[i + 1];
    if (p0 >= level && p1 < level && p1 > 0.0) return (std::log(p1) - std::log(p0)) / (s1 - s0);
  }
  return 0.0;
}

/// The values of `f` on a fine grid of mean SNR, for crossings.
template <typename F>
std::vector<std::pair<double, double>> sampled(double from, double to, double step, F f) {
  std::vector<std::pair<double, double>> c;
  for (double m = from; m <= to + 1e-9; m += step) c.emplace_back(m, f(m));
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"PER in Rayleigh block fading against the AWGN curve averaged over the fades"};
  unsigned frames = 20000;
  unsigned awgn_frames = 0;
  std::vector<std::string> phys = {"gmsk", "dsss"};
  double mean_from = 0.0, mean_to = 30.0, mean_step = 3.0, awgn_step = 0.5;
  std::vector<double> levels = {0.3, 0.1, 0.03, 0.01};
  double target_db = 1.0;
  unsigned jobs = std::max(1U, std::thread::hardware_concurrency());
  std::string csv;
  app.add_option("--frames", frames, "Frames per fading point")
      ->capture_default_str()
      ->check(CLI::Range(10U, 100000U));
  app.add_option("--awgn-frames", awgn_frames, "Frames per AWGN point (0: a quarter of --frames)")
      ->capture_default_str();
  app.add_option("--phys", phys, "PHYs to measure (gmsk, dsss)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"gmsk", "dsss"}));
  app.add_option("--mean-from", mean_from, "Lowest mean SNR (dB)")->capture_default_str();
  app.add_option("--mean-to", mean_to, "Highest mean SNR (dB)")->capture_default_str();
  app.add_option("--mean-step", mean_step, "Mean SNR step (dB)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--awgn-step", awgn_step, "AWGN grid step (dB)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--levels", levels, "PER levels of the gaps")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--target", target_db, "Largest acceptable |gap| (dB)")->capture_default_str();
  app.add_option("--jobs", jobs, "Points measured in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1U, 64U));
  app.add_option("--csv", csv, "Write every point, the reference curves and the fades here");
  CLI11_PARSE(app, argc, argv);
  if (awgn_frames == 0) awgn_frames = std::max(10U, frames / 4);

  const auto t_start = std::chrono::steady_clock::now();
  std::vector<PhyCase> cases;
  for (const PhyCase& pc : known_phys()) {
    if (std::find(phys.begin(), phys.end(), pc.name) != phys.end()) cases.push_back(pc);
  }
  const std::vector<LocalPosition> points = hop_points(frames);
  const std::vector<double> fades = fade_powers(points);

  std::vector<Job> todo;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    for (double u = cases[c].awgn_from_db; u <= cases[c].awgn_to_db + 1e-9; u += awgn_step) {
      todo.push_back({c, false, u, awgn_frames});
    }
    for (double m = mean_from; m <= mean_to + 1e-9; m += mean_step) {
      todo.push_back({c, true, m, frames});
    }
  }
  // Slowest first (the fading points, then the rest), so that the workers
  // finish together.
  std::stable_partition(todo.begin(), todo.end(), [](const Job& j) { return j.faded; });
  std::vector<Outcome> done(todo.size());
  std::atomic<std::size_t> next{0};
  std::mutex print;
  const auto worker = [&] {
    while (true) {
      const std::size_t i = next.fetch_add(1);
      if (i >= todo.size()) return;
      const Job& j = todo[i];
      done[i] = run_job(cases[j.phy], j, points);
      const std::lock_guard lock(print);
      std::printf("  %-5s %-6s %6.2f dB  %5llu/%u delivered  (%.1f s)\n", cases[j.phy].name.c_str(),
                  j.faded ? "fading" : "awgn", j.snr_db,
                  static_cast<unsigned long long>(done[i].delivered), j.frames, done[i].wall_s);
      std::fflush(stdout);
    }
  };
  std::printf(
      "fading_per: %zu points on %u threads (%u frames per fading point, %u per AWGN "
      "point)\n",
      todo.size(), jobs, frames, awgn_frames);
  {
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < std::min<std::size_t>(jobs, todo.size()); ++w)
      pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }

  // The fade sample against Exp(1).
  double mean_x = 0.0;
  for (const double x : fades) mean_x += x;
  mean_x /= static_cast<double>(fades.size());
  std::printf("\nfade sample: %zu frames, mean |h|^2 = %.3f (1 expected);", fades.size(), mean_x);
  for (const double q : {0.3, 0.1, 0.03, 0.01}) {
    const auto below = std::count_if(fades.begin(), fades.end(), [q](double x) { return x < q; });
    std::printf(" P(|h|^2 < %g) = %.4f (Exp(1): %.4f)", q,
                static_cast<double>(below) / static_cast<double>(fades.size()), -std::expm1(-q));
  }
  std::printf("\n");
  std::printf(
      "columns: measured PER; reference = AWGN curve averaged over Exp(1); realized = AWGN curve "
      "averaged over this run's fades; ref. tail = part of the reference from above the last "
      "AWGN point with errors (extrapolated)\n");

  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    out << "phy,kind,snr_db,frames,delivered,per\n";
  }
  bool pass = true;
  bool complete = true;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const PhyCase& pc = cases[c];
    std::vector<AwgnCurve::Point> awgn;
    std::vector<std::pair<double, double>> measured;
    std::vector<unsigned> measured_frames;
    for (std::size_t i = 0; i < todo.size(); ++i) {
      if (todo[i].phy != c) continue;
      complete = complete && done[i].pending == 0;
      const double per =
          1.0 - static_cast<double>(done[i].delivered) / static_cast<double>(todo[i].frames);
      if (todo[i].faded) {
        measured.emplace_back(todo[i].snr_db, per);
      } else {
        awgn.push_back({todo[i].snr_db, per, todo[i].frames});
      }
      if (out) {
        out << pc.name << "," << (todo[i].faded ? "fading" : "awgn") << "," << todo[i].snr_db << ","
            << todo[i].frames << "," << done[i].delivered << "," << per << "\n";
      }
    }
    std::sort(measured.begin(), measured.end());
    const AwgnCurve curve(awgn);
    std::printf(
        "\n%s (%s): AWGN grid %.1f..%.1f dB, PER %.4f at its first point, last point with "
        "errors %.1f dB\n",
        pc.name.c_str(), pc.phy.label().c_str(), curve.first_db(), curve.points().back().snr_db,
        curve.points().front().per, curve.last_with_errors_db());
    std::printf("  %-5s %9s %7s %10s %10s %10s %10s\n", "PHY", "mean SNR", "frames", "measured",
                "reference", "realized", "ref. tail");
    for (const auto& [m, per] : measured) {
      double tail = 0.0;
      const double ref = curve.rayleigh_average(m, &tail);
      const double real = curve.realized_average(m, fades);
      std::printf("  %-5s %6.1f dB %7u %10.4f %10.4f %10.4f %10.2e\n", pc.name.c_str(), m, frames,
                  per, ref, real, tail);
      if (out) out << pc.name << ",realized," << m << ",0,," << real << "\n";
    }
    const auto reference = sampled(mean_from - 3.0, mean_to + 3.0, 0.01,
                                   [&](double m) { return curve.rayleigh_average(m); });
    const auto realized = sampled(mean_from - 3.0, mean_to + 3.0, 0.05,
                                  [&](double m) { return curve.realized_average(m, fades); });
    if (out) {
      for (std::size_t i = 0; i < reference.size(); i += 10) {
        out << pc.name << ",reference," << reference[i].first << ",0,," << reference[i].second
            << "\n";
      }
    }
    // A point without errors counts as half a frame's worth (for crossings).
    auto floored = measured;
    for (auto& point : floored) point.second = std::max(point.second, 0.5 / frames);
    std::printf("  gaps (mean SNR of the measurement minus the reference's, at equal PER):\n");
    for (const double level : levels) {
      const auto at_meas = crossing(floored, level);
      const auto at_ref = crossing(reference, level);
      const auto at_real = crossing(realized, level);
      if (!at_meas || !at_ref || !at_real) {
        std::printf("    PER %-5g: not crossed within %.0f..%.0f dB\n", level, mean_from, mean_to);
        pass = false;
        continue;
      }
      const double slope = log_slope_at(floored, level);
      const double sigma =
          slope != 0.0 ? std::sqrt((1.0 - level) / (frames * level)) / std::abs(slope) : 0.0;
      const double gap = *at_meas - *at_ref;
      const bool ok = std::abs(gap) <= target_db;
      pass = pass && ok;
      std::printf(
          "    PER %-5g: measured %5.2f dB, reference %5.2f dB: gap %+5.2f dB (+-%.2f "
          "statistical); realized reference %5.2f dB: fade sample %+5.2f, receivers "
          "%+5.2f  %s\n",
          level, *at_meas, *at_ref, gap, sigma, *at_real, *at_real - *at_ref, *at_meas - *at_real,
          ok ? "ok" : "OVER");
    }
  }
  if (out) {
    std::printf("\nfading_per: wrote %s\n", csv.c_str());
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (!complete) std::printf("fading_per: some frames had no outcome at the end of a run\n");
  std::printf("fading_per: %s: every |gap| %s %.1f dB (%.0f s)\n",
              pass && complete ? "PASS" : "FAIL", pass ? "<=" : "not <=", target_db, wall);
  return pass && complete ? 0 : 1;
}
