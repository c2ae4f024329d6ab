#include "rfsitl/channel/channel_matrix.hpp"

#include <stdexcept>
#include <utility>

#include "rfsitl/channel/geodesy.hpp"

namespace rfsitl::channel {

ChannelMatrix::ChannelMatrix(std::size_t num_nodes, std::shared_ptr<const LinkModel> model)
    : n_(num_nodes),
      model_(std::move(model)),
      positions_(num_nodes),
      coeff_(num_nodes * num_nodes, cf32{0.0f, 0.0f}) {
  if (!model_) {
    throw std::invalid_argument("ChannelMatrix: link model must not be null");
  }
}

void ChannelMatrix::set_position(std::size_t i, std::optional<Ecef> pos) {
  // Not a hot path (a location feed updates a few times a second), so the
  // index is checked: a bad node index must not corrupt another node's links.
  positions_.at(i) = pos;
  recompute(i);
}

std::optional<double> ChannelMatrix::distance(std::size_t a, std::size_t b) const {
  const auto& pa = positions_.at(a);
  const auto& pb = positions_.at(b);
  if (!pa || !pb) {
    return std::nullopt;
  }
  return distance_m(*pa, *pb);
}

void ChannelMatrix::recompute(std::size_t i) {
  const std::optional<Ecef>& pi = positions_[i];
  for (std::size_t j = 0; j < n_; ++j) {
    const std::optional<Ecef>& pj = positions_[j];
    cf32 c{0.0f, 0.0f};
    if (pi && pj) {
      // The diagonal is the model at exactly d = 0 (the node hears itself),
      // not whatever rounding distance_m(p, p) might produce.
      c = model_->coefficient(j == i ? 0.0 : distance_m(*pi, *pj));
    }
    // LinkModel depends only on distance, so the link is reciprocal: one
    // evaluation fills both row i (i receiving) and column i (i transmitting).
    coeff_[i * n_ + j] = c;
    coeff_[j * n_ + i] = c;
  }
}

}  // namespace rfsitl::channel
