#pragma once
/// The N x N matrix of link coefficients, kept in step with node positions.
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rfsitl/channel/link_budget.hpp"
#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

/// Owned by the engine thread; not thread-safe. Node indices are 0..N-1.
class ChannelMatrix {
 public:
  /// Precondition: budget != nullptr. All nodes start without a position (no
  /// links). `origin` is where the local frame that stages see is centred.
  ChannelMatrix(std::size_t num_nodes, std::shared_ptr<const LinkBudget> budget,
                const GeodeticPosition& origin = {});

  std::size_t size() const { return n_; }

  /// Sets or clears (nullopt) node `i`'s position and recomputes its row and column.
  /// A node without a known position has coefficient 0 to and from every node,
  /// itself included.
  void set_position(std::size_t i, std::optional<Ecef> pos);

  const std::optional<Ecef>& position(std::size_t i) const { return positions_[i]; }

  /// Coefficient of the link from transmitter `tx` to receiver `rx`.
  cf32 coefficient(std::size_t tx, std::size_t rx) const { return coeff_[rx * n_ + tx]; }

  /// Power gain |c|^2 of the link from `tx` to `rx`.
  float power_gain(std::size_t tx, std::size_t rx) const { return std::norm(coefficient(tx, rx)); }

  /// Row of coefficients seen by receiver `rx`, indexed by transmitter.
  std::span<const cf32> receiver_row(std::size_t rx) const { return {coeff_.data() + rx * n_, n_}; }

  /// Distance in metres, or nullopt when either position is unknown.
  std::optional<double> distance(std::size_t a, std::size_t b) const;

 private:
  void recompute(std::size_t i);
  LinkGeometry geometry(std::size_t tx, std::size_t rx) const;

  std::size_t n_;
  std::shared_ptr<const LinkBudget> budget_;
  GeodeticPosition origin_;
  std::vector<std::optional<Ecef>> positions_;
  std::vector<LocalPosition> local_;  // of the nodes with a position
  std::vector<cf32> coeff_;           // row-major by receiver: coeff_[rx * n + tx]
};

}  // namespace rfsitl::channel
