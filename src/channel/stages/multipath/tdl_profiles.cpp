// TR 38.901's tapped-delay-line profiles (Tables 7.7.2-1 to 7.7.2-3, the NLOS
// ones) and what the stage does with a list of taps.
#include <cmath>
#include <numeric>

#include "rfsitl/channel/stages/multipath.hpp"

namespace rfsitl::channel::multipath {
namespace {

struct Table {
  std::span<const double> normalised_delay;  // units of the RMS delay spread
  std::span<const double> power_db;
};

constexpr double kTdlADelay[] = {0.0000, 0.3819, 0.4025, 0.5868, 0.4610, 0.5375, 0.6708, 0.5750,
                                 0.7618, 1.5375, 1.8978, 2.2242, 2.1718, 2.4942, 2.5119, 3.0582,
                                 4.0810, 4.4579, 4.5695, 4.7966, 5.0066, 5.3043, 9.6586};
constexpr double kTdlAPower[] = {-13.4, 0.0,   -2.2,  -4.0,  -6.0,  -8.2,  -9.9,  -10.5,
                                 -7.5,  -15.9, -6.6,  -16.7, -12.4, -15.2, -10.8, -11.3,
                                 -12.7, -16.2, -18.3, -18.9, -16.6, -19.9, -29.7};
constexpr double kTdlBDelay[] = {0.0000, 0.1072, 0.2155, 0.2095, 0.2870, 0.2986, 0.3752, 0.5055,
                                 0.3681, 0.3697, 0.5700, 0.5283, 1.1021, 1.2756, 1.5474, 1.7842,
                                 2.0169, 2.8294, 3.0219, 3.6187, 4.1067, 4.2790, 4.7834};
constexpr double kTdlBPower[] = {0.0,  -2.2,  -4.0, -3.2,  -9.8,  -1.2, -3.4, -5.2,
                                 -7.6, -3.0,  -8.9, -9.0,  -4.8,  -5.7, -7.5, -1.9,
                                 -7.6, -12.2, -9.8, -11.4, -14.9, -9.2, -11.3};
constexpr double kTdlCDelay[] = {0.0000, 0.2099, 0.2219, 0.2329, 0.2176, 0.6366, 0.6448, 0.6560,
                                 0.6584, 0.7935, 0.8213, 0.9336, 1.2285, 1.3083, 2.1704, 2.7105,
                                 4.2589, 4.6003, 5.4902, 5.6077, 6.3065, 6.6374, 7.0427, 8.6523};
constexpr double kTdlCPower[] = {-4.4,  -1.2,  -3.5,  -5.2,  -2.5,  0.0,   -2.2,  -3.9,
                                 -7.4,  -7.1,  -10.7, -11.1, -5.1,  -6.8,  -8.7,  -13.2,
                                 -13.9, -13.9, -15.8, -17.1, -16.0, -15.7, -21.6, -22.8};

static_assert(std::size(kTdlADelay) == std::size(kTdlAPower));
static_assert(std::size(kTdlBDelay) == std::size(kTdlBPower));
static_assert(std::size(kTdlCDelay) == std::size(kTdlCPower));

Table table(MultipathProfile p) {
  switch (p) {
    case MultipathProfile::kTdlA:
      return {kTdlADelay, kTdlAPower};
    case MultipathProfile::kTdlB:
      return {kTdlBDelay, kTdlBPower};
    default:
      return {kTdlCDelay, kTdlCPower};
  }
}

}  // namespace

std::vector<MultipathTap> profile_taps(const MultipathSettings& settings) {
  if (settings.profile == MultipathProfile::kTaps) return settings.taps;
  const Table t = table(settings.profile);
  std::vector<MultipathTap> taps;
  for (std::size_t i = 0; i < t.normalised_delay.size(); ++i) {
    taps.push_back({t.normalised_delay[i] * settings.delay_spread_ns, t.power_db[i]});
  }
  return taps;
}

std::vector<Path> normalised_paths(std::span<const MultipathTap> taps) {
  double total = 0.0;
  for (const MultipathTap& t : taps) total += std::pow(10.0, t.gain_db / 10.0);
  std::vector<Path> paths;
  for (const MultipathTap& t : taps) {
    paths.push_back({t.delay_ns * 1e-9, std::sqrt(std::pow(10.0, t.gain_db / 10.0) / total)});
  }
  return paths;
}

double rms_delay_spread_s(std::span<const Path> paths) {
  double power = 0.0;
  double mean = 0.0;
  double square = 0.0;
  for (const Path& p : paths) {
    const double w = std::norm(p.gain);
    power += w;
    mean += w * p.delay_s;
    square += w * p.delay_s * p.delay_s;
  }
  mean /= power;
  return std::sqrt(std::max(0.0, square / power - mean * mean));
}

}  // namespace rfsitl::channel::multipath
