#include "rfsitl/monitor/live_view_share.hpp"

#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace rfsitl::monitor {
namespace {

constexpr std::uint8_t kVersion = 1;

template <typename T>
void append(std::vector<std::uint8_t>& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  // resize + memcpy: GCC 12 at -O3 takes insert() of a value's bytes for an
  // overflow (-Wstringop-overflow, a false positive that -Werror makes fatal).
  const std::size_t at = out.size();
  out.resize(at + sizeof v);
  std::memcpy(out.data() + at, &v, sizeof v);
}

/// Reads values in order; every read checks what is left.
class Cursor {
 public:
  explicit Cursor(std::span<const std::uint8_t> in) : in_(in) {}
  template <typename T>
  T take(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (in_.size() - at_ < sizeof(T)) bad(std::string("short in ") + what);
    T v;
    std::memcpy(&v, in_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  /// A count of items of at least `each` bytes, no more than what is left holds.
  std::uint32_t items(std::size_t each, const char* what) {
    const auto n = take<std::uint32_t>(what);
    if (static_cast<std::uint64_t>(n) * each > in_.size() - at_) {
      bad(std::string("count of ") + what + " beyond its end");
    }
    return n;
  }
  std::uint32_t index(std::size_t limit, const char* what) {
    const auto i = take<std::uint32_t>(what);
    if (i >= limit) bad(std::string(what) + " index " + std::to_string(i) + " out of range");
    return i;
  }
  void finish() const {
    if (at_ != in_.size()) bad(std::to_string(in_.size() - at_) + " byte(s) after its end");
  }
  [[noreturn]] static void bad(const std::string& why) {
    throw std::invalid_argument("live view share: " + why);
  }

 private:
  std::span<const std::uint8_t> in_;
  std::size_t at_ = 0;
};

}  // namespace

std::vector<std::uint8_t> encode_share(const LiveViewShare& share) {
  std::vector<std::uint8_t> out;
  append(out, kVersion);
  append(out, static_cast<std::uint32_t>(share.watched.size()));
  for (const std::uint32_t node : share.watched) append(out, node);
  append(out, static_cast<std::uint32_t>(share.links.size()));
  for (const auto& c : share.links) {
    append(out, c.cell);
    append(out, c.received);
    append(out, c.lost);
  }
  append(out, static_cast<std::uint32_t>(share.spectra.size()));
  for (const auto& s : share.spectra) {
    append(out, s.node);
    append(out, static_cast<std::uint32_t>(s.db.size()));
    for (const float v : s.db) append(out, v);
  }
  append(out, static_cast<std::uint32_t>(share.constellations.size()));
  for (const auto& [node, c] : share.constellations) {
    append(out, node);
    append(out, c.time);
    append(out, c.src);
    append(out, c.dst);
    append(out, c.serial);
    append(out, static_cast<std::uint8_t>(c.payload_valid ? 1 : 0));
    append(out, static_cast<std::uint32_t>(c.points.size()));
    for (const cf32& p : c.points) append(out, p);
  }
  return out;
}

LiveViewShare decode_share(std::span<const std::uint8_t> bytes, std::size_t nodes) {
  Cursor in(bytes);
  if (const auto v = in.take<std::uint8_t>("version"); v != kVersion) {
    Cursor::bad("format version " + std::to_string(v) + ", not " + std::to_string(kVersion));
  }
  LiveViewShare s;
  for (std::uint32_t k = in.items(4, "watched nodes"); k > 0; --k) {
    s.watched.push_back(in.index(nodes, "watched node"));
  }
  for (std::uint32_t k = in.items(12, "link cells"); k > 0; --k) {
    LiveViewShare::LinkCell c;
    c.cell = in.index(nodes * nodes, "link cell");
    c.received = in.take<std::uint32_t>("link cells");
    c.lost = in.take<std::uint32_t>("link cells");
    s.links.push_back(c);
  }
  for (std::uint32_t k = in.items(8, "spectra"); k > 0; --k) {
    LiveViewShare::Spectrum sp;
    sp.node = in.index(nodes, "spectrum node");
    const std::uint32_t bins = in.items(sizeof(float), "spectrum bins");
    if (bins != LiveView::kSpectrumBins) {
      Cursor::bad("a spectrum of " + std::to_string(bins) + " bins, not " +
                  std::to_string(LiveView::kSpectrumBins));
    }
    sp.db.resize(bins);
    for (float& v : sp.db) v = in.take<float>("spectrum bins");
    s.spectra.push_back(std::move(sp));
  }
  for (std::uint32_t k = in.items(23, "constellations"); k > 0; --k) {
    const std::uint32_t node = in.index(nodes, "constellation node");
    Constellation c;
    c.time = in.take<SampleTime>("constellation");
    c.src = in.take<NodeId>("constellation");
    c.dst = in.take<NodeId>("constellation");
    c.serial = in.take<std::uint32_t>("constellation");
    c.payload_valid = in.take<std::uint8_t>("constellation") != 0;
    const std::uint32_t points = in.items(sizeof(cf32), "constellation points");
    if (points > LiveView::kMaxConstellationPoints) {
      Cursor::bad(std::to_string(points) + " constellation points, more than " +
                  std::to_string(LiveView::kMaxConstellationPoints));
    }
    c.points.resize(points);
    for (cf32& p : c.points) p = in.take<cf32>("constellation points");
    s.constellations.emplace_back(node, std::move(c));
  }
  in.finish();
  return s;
}

}  // namespace rfsitl::monitor
