#pragma once
/// The interval a numeric setting (or a numeric field of a list setting's
/// items) must lie in, and the words every message and table uses for it.
#include <optional>
#include <string>

namespace rfsitl::config {

/// Shortest text that reads back as the same double: 0.5, 1e+08, -3.
std::string number_text(double v);

/// An interval of a numeric setting. NaN and infinities are never inside.
struct Range {
  double lo = 0;
  double hi = 0;
  bool lo_open = false;
  bool hi_open = false;
  bool contains(double v) const;

  /// The interval in words, as for a real: "finite", ">= 0", "> 0", "[0.2, 1]", "(0, 1]".
  std::string text() const;

  /// Why the real `v` is outside ("must be >= 0, got -3", "must be in (0, 1], got 2",
  /// "must be a finite number, got nan"), or nullopt when it is inside.
  std::optional<std::string> reject_reason(double v) const;
};

}  // namespace rfsitl::config
