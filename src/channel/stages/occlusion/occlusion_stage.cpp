// The occlusion stage: its settings, declared once, and the stage that adds the
// losses of the body-frame cones each end's direction falls in.
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "rfsitl/channel/stages/occlusion.hpp"

namespace rfsitl::channel {
namespace {

const config::RecordFields<OcclusionSector>& sector_fields() {
  using P = OcclusionSector;
  static const auto f =
      config::RecordFields<P>()
          .required("azimuth_deg", &P::azimuth_deg, "deg", {-360.0, 360.0},
                    "the cone's axis, clockwise from the nose (90: the right wing)")
          .required("elevation_deg", &P::elevation_deg, "deg", {-90.0, 90.0},
                    "the cone's axis, above the body's x-y plane (-90: straight down)")
          .required("half_angle_deg", &P::half_angle_deg, "deg", {0.0, 180.0},
                    "the cone's half-angle")
          .required("loss_db", &P::loss_db, "dB", {0.0, 200.0},
                    "what a direction inside the cone loses");
  return f;
}

// The cosine test below, with room for the rounding of a direction that lies
// exactly on a cone's edge or (half-angle 0) its axis.
constexpr double kCosineSlack = 1e-12;

}  // namespace

const config::Fields<OcclusionSettings>& occlusion_fields() {
  using S = OcclusionSettings;
  static const auto f = config::Fields<S>().records(
      "sectors", &S::sectors, sector_fields(), 0, 64,
      "body-frame cones the airframe blocks, at both ends of every link");
  return f;
}

namespace occlusion {

double loss_db(const std::vector<OcclusionSector>& sectors, const BodyVector& u) {
  double loss = 0.0;
  for (const OcclusionSector& s : sectors) {
    const BodyVector axis = body_vector_at(s.azimuth_deg, s.elevation_deg);
    const double cos_half = std::cos(s.half_angle_deg * std::numbers::pi / 180.0);
    if (dot(u, axis) >= cos_half - kCosineSlack) loss += s.loss_db;
  }
  return loss;
}

}  // namespace occlusion

namespace {

class OcclusionStage final : public GainStage {
 public:
  explicit OcclusionStage(std::vector<OcclusionSector> sectors) : sectors_(std::move(sectors)) {}

  std::complex<double> gain(const LinkGeometry& link) const override {
    if (link.tx.index == link.rx.index) return 1.0;
    const double loss = end_loss_db(link.tx, link.rx) + end_loss_db(link.rx, link.tx);
    return std::pow(10.0, -loss / 20.0);
  }

  bool reciprocal() const override { return false; }
  bool depends_on_attitude() const override { return true; }

 private:
  double end_loss_db(const LinkEnd& from, const LinkEnd& to) const {
    const std::optional<BodyVector> d = direction_in_body(from, to);
    return d ? occlusion::loss_db(sectors_, *d) : 0.0;
  }

  std::vector<OcclusionSector> sectors_;
};

}  // namespace

ChannelStageComponent occlusion_component() {
  return {occlusion_fields().info("channel", "occlusion",
                                  "losses of the directions the airframe blocks, at both ends"),
          [](const config::Settings& settings, const StageContext&) {
            return std::make_unique<OcclusionStage>(occlusion_fields().build(settings).sectors);
          }};
}

}  // namespace rfsitl::channel
