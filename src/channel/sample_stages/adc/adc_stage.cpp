/// An analog-to-digital (or, on the transmit side, digital-to-analog)
/// converter: each of I and Q clipped at the full scale A and quantized to
/// 2^bits levels, mid-rise (no level at zero, as a two's-complement converter
/// read with its half-LSB offset):
///   q = 2A / 2^bits,  k = clamp(floor(v / q), -2^(bits-1), 2^(bits-1) - 1),
///   out = (k + 1/2) q.
/// A is given in dB over the samples' unit RMS: on a receiver the noise floor
/// (so full_scale_db is the headroom a gain stage leaves above the noise; a
/// signal more than that above the floor clips), on a transmitter its signal.
/// Quantization noise is q^2 / 12 per branch: with the defaults (12 bits, 30
/// dB) it is 44 dB below the receiver's noise floor.
/// The output stays in the input's units, so the stages after it and the
/// receiver see the converter's levels scaled back, as a radio's driver hands
/// out samples scaled to +-1.
#include <algorithm>
#include <cmath>
#include <memory>

#include "rfsitl/channel/sample_stage.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {
namespace {

struct AdcSettings {
  std::uint64_t bits = 12;
  double full_scale_db = 30.0;
};

const config::Fields<AdcSettings>& adc_fields() {
  using S = AdcSettings;
  static const auto f =
      config::Fields<S>()
          .integer("bits", &S::bits, "bit", 1, 24, "resolution of each of I and Q")
          .real("full_scale_db", &S::full_scale_db, "dB", {-20.0, 120.0},
                "the largest |I| or |Q| over the samples' unit RMS (a receiver's noise floor, a "
                "transmitter's signal); beyond it the converter clips");
  return f;
}

class AdcStage final : public SampleStage {
 public:
  explicit AdcStage(const AdcSettings& s)
      : full_scale_(static_cast<float>(std::pow(10.0, s.full_scale_db / 20.0))),
        half_levels_(static_cast<float>(std::ldexp(1.0, static_cast<int>(s.bits) - 1))),
        step_(full_scale_ / half_levels_),
        inv_step_(half_levels_ / full_scale_) {}

  void apply(std::size_t /*node*/, SampleTime /*first_sample*/, std::span<cf32> x) const override {
    for (cf32& v : x) v = {convert(v.real()), convert(v.imag())};
  }

 private:
  float convert(float v) const {
    const float k = std::clamp(std::floor(v * inv_step_), -half_levels_, half_levels_ - 1.0F);
    return (k + 0.5F) * step_;
  }

  float full_scale_;
  float half_levels_;  // 2^(bits - 1)
  float step_;         // q
  float inv_step_;
};

}  // namespace

SampleStageComponent adc_component() {
  static const config::ComponentInfo info = adc_fields().info(
      "sample", "adc",
      "a converter: I and Q clipped at full scale and quantized to 2^bits levels each");
  return {info, [](const config::Settings& s, const SampleStageContext&) {
            return std::make_unique<AdcStage>(adc_fields().build(s));
          }};
}

}  // namespace rfsitl::channel
