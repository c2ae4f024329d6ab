// The mobility model "gauss_markov": speed and heading with memory, reflected at a box.
#include "../component_support.hpp"
#include "rfsitl/position/mobility/gauss_markov_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using namespace detail;

struct GaussMarkovFields : BoxFields {
  double alpha = 0.85, mean_speed_mps = 10, mean_direction_rad = 0, speed_sd_mps = 2,
         direction_sd_rad = 0.5, update_interval_s = 1;
  GaussMarkovSettings model(const MobilityContext& c) const {
    GaussMarkovSettings s;
    s.alpha = alpha;
    s.mean_speed_mps = mean_speed_mps;
    s.mean_direction_rad = mean_direction_rad;
    s.speed_sd_mps = speed_sd_mps;
    s.direction_sd_rad = direction_sd_rad;
    s.update_interval_s = update_interval_s;
    return with_shared(s, c);
  }
};

const config::Fields<GaussMarkovFields>& gauss_markov_fields() {
  using S = GaussMarkovFields;
  static const auto f =
      with_box<S>()
          .real("alpha", &S::alpha, "", {0, 1}, "memory: 0 memoryless, 1 straight lines")
          .real("mean_speed_mps", &S::mean_speed_mps, "m/s", {0, 1e4}, "mean speed")
          .real("mean_direction_rad", &S::mean_direction_rad, "rad", {-10, 10},
                "mean heading, counter-clockwise from east")
          .real("speed_sd_mps", &S::speed_sd_mps, "m/s", {0, 1e4}, "speed standard deviation")
          .real("direction_sd_rad", &S::direction_sd_rad, "rad", {0, 10},
                "heading standard deviation")
          .real("update_interval_s", &S::update_interval_s, "s", {0, 1e6, true},
                "time between redraws of speed and heading")
          .rule([](const S& s) { checked(s.model(MobilityContext{})); });
  return f;
}

}  // namespace

MobilityComponent gauss_markov_component() {
  return {
      gauss_markov_fields().info("mobility", "gauss_markov",
                                 "Gauss-Markov: speed and heading with memory, reflected at a box"),
      [](const config::Settings& s, const MobilityContext& c) -> std::unique_ptr<MobilityModel> {
        return std::make_unique<GaussMarkovModel>(gauss_markov_fields().build(s).model(c));
      }};
}

}  // namespace rfsitl::position::mobility
