#pragma once
/// The occlusion stage: the airframe (fuselage, battery, landing gear) blocks
/// some directions from the antenna. Every node carries the same airframe.
///
/// Model. `sectors` lists cones fixed to the body, each with its axis at
/// (azimuth_deg, elevation_deg) in body_frame.hpp's angles (azimuth clockwise
/// from the nose, elevation above the body's x-y plane: -90 is straight down),
/// its half-angle, and its loss. At each end, the direction of the other end
/// in that end's body frame loses the loss of every cone it falls in (the
/// boundary counts as inside; overlapping cones add). The link's loss is the
/// sum over both ends: gain = 10^(-loss_db / 20), real. A node without an
/// attitude is level and faces north; a node's link to itself, or to a node
/// at the same place (no direction), loses nothing. The stage re-evaluates a
/// node's links when it turns (depends_on_attitude) and declares itself not
/// reciprocal (with one airframe on every node the sum is in fact symmetric).
#include <complex>
#include <vector>

#include "rfsitl/channel/body_frame.hpp"
#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

/// A body-frame cone the airframe blocks.
struct OcclusionSector {
  double azimuth_deg = 0.0;     ///< the axis, clockwise from the nose
  double elevation_deg = 0.0;   ///< the axis, above the body's x-y plane
  double half_angle_deg = 0.0;  ///< the cone's half-angle, [0, 180]
  double loss_db = 0.0;         ///< what a direction inside it loses, >= 0
};

struct OcclusionSettings {
  std::vector<OcclusionSector> sectors;
};

const config::Fields<OcclusionSettings>& occlusion_fields();
ChannelStageComponent occlusion_component();

namespace occlusion {

/// The loss in dB of the direction `u` (a unit body vector) through
/// `sectors`: the sum of the losses of the cones it falls in. Pure.
double loss_db(const std::vector<OcclusionSector>& sectors, const BodyVector& u);

}  // namespace occlusion
}  // namespace rfsitl::channel
