#include "rfsitl/channel/front_end.hpp"

#include <cmath>
#include <numbers>
#include <vector>

namespace rfsitl::channel {

const config::Fields<FrontEndSettings>& front_end_fields() {
  using S = FrontEndSettings;
  static const auto f =
      config::Fields<S>()
          .real("cfo_hz", &S::cfo_hz, "Hz", {-1e7, 1e7},
                "the local oscillator's offset from the carrier (the same for every node)")
          .real("cfo_spread_hz", &S::cfo_spread_hz, "Hz", {0.0, 1e6},
                "each node's own offset on top: drawn once from N(0, this^2) (20 ppm at "
                "2.4 GHz is 48 kHz)")
          .real("phase_noise_dbc_hz", &S::phase_noise_dbc_hz, "dBc/Hz", {-200.0, -20.0},
                "single-sideband phase noise at phase_noise_offset_hz, a free-running "
                "oscillator's (Wiener) 1/f^2 slope; -200: none")
          .real("phase_noise_offset_hz", &S::phase_noise_offset_hz, "Hz", {1.0, 1e8},
                "the offset from the carrier at which phase_noise_dbc_hz is given")
          .real("iq_imbalance_db", &S::iq_imbalance_db, "dB", {-10.0, 10.0},
                "the Q branch's gain over the I branch's")
          .real("iq_imbalance_deg", &S::iq_imbalance_deg, "deg", {-45.0, 45.0},
                "the Q branch's phase skew from quadrature")
          .real("dc_offset", &S::dc_offset, "", {0.0, 100.0},
                "a constant added, in units of the signal's RMS amplitude (the transmitter's "
                "unit power; the receiver's noise floor)");
  return f;
}

const config::ComponentInfo& front_end_info() {
  static const config::ComponentInfo info = front_end_fields().info(
      "sample", "impairments",
      "front-end imperfections of every node: carrier offset, phase noise, I/Q imbalance, DC "
      "offset (channel.impairments.tx and .rx are short for this stage first in tx_stages and "
      "rx_stages)");
  return info;
}

bool is_ideal(const FrontEndSettings& s) {
  return s.cfo_hz == 0.0 && s.cfo_spread_hz == 0.0 && s.phase_noise_dbc_hz <= -200.0 &&
         s.iq_imbalance_db == 0.0 && s.iq_imbalance_deg == 0.0 && s.dc_offset == 0.0;
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// One standard normal draw: the real part of unit-variance complex noise is
/// N(0, 1/2), so the source is built with variance 2.
double normal(const NoiseSource& source, std::uint64_t index) {
  cf32 v{};
  source.fill(std::span(&v, 1), index);
  return static_cast<double>(v.real());
}

}  // namespace

FrontEnd::FrontEnd(const FrontEndSettings& s, FrontEndSide side, double sample_rate_hz,
                   std::size_t tick_samples, std::uint64_t seed, std::uint64_t stream)
    : side_(side), fs_(sample_rate_hz), tick_(tick_samples), offset_hz_(s.cfo_hz) {
  // Streams: 3 per front end (its offset draw, per-sample and per-tick phase
  // noise), above the receivers' noise streams (< 2^32) and the shared one.
  const std::uint64_t base = (std::uint64_t{2} << 32) + 3 * stream;
  if (s.cfo_spread_hz > 0.0) {
    offset_hz_ += s.cfo_spread_hz * normal(NoiseSource(seed, base, 2.0F), 0);
  }
  if (s.phase_noise_dbc_hz > -200.0) {
    const double linewidth_hz = std::numbers::pi * s.phase_noise_offset_hz *
                                s.phase_noise_offset_hz *
                                std::pow(10.0, s.phase_noise_dbc_hz / 10.0);
    phase_step_sigma_ = std::sqrt(kTwoPi * linewidth_hz / sample_rate_hz);
    per_sample_.emplace(seed, base + 1, 2.0F);
    per_tick_.emplace(seed, base + 2, 2.0F);
  }
  const double g = std::pow(10.0, s.iq_imbalance_db / 20.0);
  const double p = s.iq_imbalance_deg * std::numbers::pi / 180.0;
  const std::complex<double> mu = (1.0 + g * std::polar(1.0, -p)) / 2.0;
  const std::complex<double> nu = (1.0 - g * std::polar(1.0, p)) / 2.0;
  mu_ = {static_cast<float>(mu.real()), static_cast<float>(mu.imag())};
  nu_ = {static_cast<float>(nu.real()), static_cast<float>(nu.imag())};
  iq_ = s.iq_imbalance_db != 0.0 || s.iq_imbalance_deg != 0.0;
  const auto dc = static_cast<float>(s.dc_offset / std::numbers::sqrt2);
  dc_ = {dc, dc};
}

void FrontEnd::advance(SampleTime tick_start) {
  if (!per_tick_) return;
  phi_start_ = tick_start == 0 ? 0.0 : phi_end_;
  tick_start_ = tick_start;
  // The tick's whole increment: the sum of tick_ per-sample steps in law.
  const auto k = static_cast<std::uint64_t>(tick_start) / tick_;
  phi_end_ = phi_start_ +
             phase_step_sigma_ * std::sqrt(static_cast<double>(tick_)) * normal(*per_tick_, k);
}

void FrontEnd::apply(SampleTime first_sample, std::span<cf32> x) const {
  if (side_ == FrontEndSide::kTransmit) {
    distort(x);
    rotate(first_sample, x);
  } else {
    rotate(first_sample, x);
    distort(x);
  }
}

/// x e^{j(2 pi f t + phi(t))}: the offset's phase is exact at the first sample
/// (in double, wrapped) and advanced by a fixed rotation; the phase noise is a
/// Brownian bridge from phi_start_ to phi_end_ over the tick.
void FrontEnd::rotate(SampleTime first_sample, std::span<cf32> x) const {
  if (offset_hz_ == 0.0 && !per_sample_) return;
  const double cycles = std::fmod(offset_hz_ / fs_ * static_cast<double>(first_sample), 1.0);
  std::complex<double> rot = std::polar(1.0, kTwoPi * cycles);
  const std::complex<double> step = std::polar(1.0, kTwoPi * offset_hz_ / fs_);
  // Per thread, not per call: receivers of different threads apply their
  // front ends at once, and the sample path allocates nothing per tick.
  thread_local std::vector<double> phi;
  thread_local std::vector<cf32> draws;
  phi.clear();
  if (per_sample_) {
    // The walk over the whole tick (so that a receiver that starts late in a
    // tick sees the same phase as one that ran all of it), then pinned to the
    // tick's end value.
    draws.resize(tick_);
    per_sample_->fill(draws, static_cast<std::uint64_t>(tick_start_));
    phi.resize(tick_ + 1);
    phi[0] = 0.0;
    for (std::size_t i = 0; i < tick_; ++i) {
      phi[i + 1] = phi[i] + phase_step_sigma_ * static_cast<double>(draws[i].real());
    }
    const double miss = phi[tick_] - (phi_end_ - phi_start_);
    for (std::size_t i = 0; i <= tick_; ++i) {
      phi[i] = phi_start_ + phi[i] - miss * static_cast<double>(i) / static_cast<double>(tick_);
    }
  }
  const auto offset = static_cast<std::size_t>(first_sample - tick_start_);
  for (std::size_t t = 0; t < x.size(); ++t) {
    std::complex<double> r = rot;
    if (!phi.empty()) r *= std::polar(1.0, phi[offset + t]);
    x[t] *= cf32{static_cast<float>(r.real()), static_cast<float>(r.imag())};
    rot *= step;
  }
}

void FrontEnd::distort(std::span<cf32> x) const {
  if (iq_) {
    for (cf32& v : x) v = mu_ * v + nu_ * std::conj(v);
  }
  if (dc_ != cf32{}) {
    for (cf32& v : x) v += dc_;
  }
}

}  // namespace rfsitl::channel
