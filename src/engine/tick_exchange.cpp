#include "tick_exchange.hpp"

#include <array>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace rfsitl::engine {
namespace {

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) { out_.clear(); }
  template <typename T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    const std::size_t at = out_.size();
    out_.resize(at + sizeof v);
    std::memcpy(out_.data() + at, &v, sizeof v);
  }
  void flag(bool b) { put(static_cast<std::uint8_t>(b ? 1 : 0)); }
  void bytes(const void* p, std::size_t n) {
    const std::size_t at = out_.size();
    out_.resize(at + n);
    if (n > 0) std::memcpy(out_.data() + at, p, n);
  }

 private:
  std::vector<std::uint8_t>& out_;
};

class Reader {
 public:
  Reader(std::span<const std::uint8_t> in, std::size_t rank, const char* what)
      : in_(in), rank_(rank), what_(what) {}
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, in_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  bool flag() { return get<std::uint8_t>() != 0; }
  /// Skips n bytes, returning where they start.
  std::size_t skip(std::size_t n) {
    need(n);
    const std::size_t start = at_;
    at_ += n;
    return start;
  }
  std::uint32_t node(std::size_t nodes) {
    const auto n = get<std::uint32_t>();
    if (n >= nodes) fail("names node index " + std::to_string(n) + " of " + std::to_string(nodes));
    return n;
  }
  std::uint32_t count(std::size_t each_at_least) {
    const auto n = get<std::uint32_t>();
    // Each item takes at least each_at_least bytes: a count beyond what is left is a lie.
    if (static_cast<std::uint64_t>(n) * each_at_least > in_.size() - at_) fail("is short");
    return n;
  }
  void done() const {
    if (at_ != in_.size()) fail("has " + std::to_string(in_.size() - at_) + " byte(s) too many");
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error("tick exchange: rank " + std::to_string(rank_) + "'s " + what_ + " " +
                             why);
  }

 private:
  void need(std::size_t n) const {
    if (in_.size() - at_ < n) fail("is short");
  }
  std::span<const std::uint8_t> in_;
  std::size_t at_ = 0;
  std::size_t rank_;
  const char* what_;
};

void put_triple(Writer& w, double a, double b, double c) {
  w.put(a);
  w.put(b);
  w.put(c);
}

constexpr std::uint8_t kMoves = 1, kKnown = 2, kWithVelocity = 4, kVelocity = 8, kAttitude = 16;

void write_update(Writer& w, const StateUpdate& u) {
  w.put(u.node);
  const std::uint8_t what =
      (u.moves ? kMoves : 0) | (u.position ? kKnown : 0) | (u.with_velocity ? kWithVelocity : 0) |
      (u.motion.velocity ? kVelocity : 0) | (u.motion.attitude ? kAttitude : 0);
  w.put(what);
  if (u.position) put_triple(w, u.position->x, u.position->y, u.position->z);
  if (const auto& v = u.motion.velocity) put_triple(w, v->vx_mps, v->vy_mps, v->vz_mps);
  if (const auto& a = u.motion.attitude) put_triple(w, a->roll_rad, a->pitch_rad, a->yaw_rad);
}

StateUpdate read_update(Reader& r, std::size_t nodes) {
  StateUpdate u;
  u.node = r.node(nodes);
  const auto what = r.get<std::uint8_t>();
  u.moves = (what & kMoves) != 0;
  u.with_velocity = (what & kWithVelocity) != 0;
  const auto triple = [&r] {
    const double a = r.get<double>();
    const double b = r.get<double>();
    return std::array<double, 3>{a, b, r.get<double>()};
  };
  if ((what & kKnown) != 0) {
    const auto p = triple();
    u.position = Ecef{p[0], p[1], p[2]};
  }
  if ((what & kVelocity) != 0) {
    const auto v = triple();
    u.motion.velocity = position::Velocity{v[0], v[1], v[2]};
  }
  if ((what & kAttitude) != 0) {
    const auto a = triple();
    u.motion.attitude = position::Attitude{a[0], a[1], a[2]};
  }
  return u;
}

// Smallest encodings, for the count checks.
constexpr std::size_t kMinReport = 4 + 4 + 1;
constexpr std::size_t kMinUpdate = 4 + 1;
constexpr std::size_t kOpBytes = 4 + 1 + 1 + 4;

}  // namespace

void write_tx_message(const TxMessage& m, std::vector<std::uint8_t>& out) {
  Writer w(out);
  w.flag(m.stop);
  w.put(static_cast<std::uint32_t>(m.reports.size()));
  for (std::size_t k = 0; k < m.reports.size(); ++k) {
    const TxReport& t = m.reports[k];
    w.put(t.node);
    w.put(t.tx_samples);
    const std::uint8_t flags = (t.has_verdict ? 1 : 0) | (t.gave_up ? 2 : 0) | (t.started ? 4 : 0) |
                               (t.awaits_verdict ? 8 : 0) | (t.first_attempt ? 16 : 0);
    w.put(flags);
    if (t.has_verdict) w.put(t.verdict_frame);
    if (t.started) {
      w.put(t.kind);
      w.put(t.serial);
      w.put(t.dst);
      w.put(t.started_len);
      w.put(t.mac_frame);
    }
    w.bytes(m.samples[k].data(), m.samples[k].size_bytes());
  }
  w.put(static_cast<std::uint32_t>(m.updates.size()));
  for (const StateUpdate& u : m.updates) write_update(w, u);
}

TxMessageView read_tx_message(std::span<const std::uint8_t> bytes, std::size_t rank,
                              std::size_t nodes, std::size_t tick_samples) {
  TxMessageView v;
  read_tx_message(bytes, rank, nodes, tick_samples, v);
  return v;
}

void read_tx_message(std::span<const std::uint8_t> bytes, std::size_t rank, std::size_t nodes,
                     std::size_t tick_samples, TxMessageView& v) {
  Reader r(bytes, rank, "TX message");
  v.stop = r.flag();
  const std::uint32_t reports = r.count(kMinReport);
  v.reports.assign(reports, TxReport{});
  v.sample_offsets.resize(reports);
  for (std::uint32_t k = 0; k < reports; ++k) {
    TxReport& t = v.reports[k];
    t.node = r.node(nodes);
    t.tx_samples = r.get<std::uint32_t>();
    if (t.tx_samples > tick_samples) r.fail("carries more samples than a tick");
    const auto flags = r.get<std::uint8_t>();
    t.has_verdict = (flags & 1) != 0;
    t.gave_up = (flags & 2) != 0;
    t.started = (flags & 4) != 0;
    t.awaits_verdict = (flags & 8) != 0;
    t.first_attempt = (flags & 16) != 0;
    if (t.has_verdict) t.verdict_frame = r.get<std::uint32_t>();
    if (t.started) {
      t.kind = r.get<std::uint8_t>();
      t.serial = r.get<std::uint32_t>();
      t.dst = r.get<NodeId>();
      t.started_len = r.get<std::uint32_t>();
      t.mac_frame = r.get<std::uint32_t>();
    }
    v.sample_offsets[k] = r.skip(t.tx_samples * sizeof(cf32));
  }
  const std::uint32_t updates = r.count(kMinUpdate);
  v.updates.clear();
  for (std::uint32_t k = 0; k < updates; ++k) v.updates.push_back(read_update(r, nodes));
  r.done();
}

void write_ledger_ops(std::span<const LedgerOp> ops, std::vector<std::uint8_t>& out) {
  Writer w(out);
  w.put(static_cast<std::uint32_t>(ops.size()));
  for (const LedgerOp& op : ops) {
    w.put(op.node);
    w.put(static_cast<std::uint8_t>(op.kind));
    w.flag(op.gave_up);
    w.put(op.id);
  }
}

void read_ledger_ops(std::span<const std::uint8_t> bytes, std::size_t rank, std::size_t nodes,
                     std::vector<LedgerOp>& out) {
  Reader r(bytes, rank, "ledger message");
  const std::uint32_t n = r.count(kOpBytes);
  for (std::uint32_t k = 0; k < n; ++k) {
    LedgerOp op;
    op.node = r.node(nodes);
    const auto kind = r.get<std::uint8_t>();
    if (kind > static_cast<std::uint8_t>(LedgerOp::Kind::kFrameDone)) r.fail("has an unknown op");
    op.kind = static_cast<LedgerOp::Kind>(kind);
    op.gave_up = r.flag();
    op.id = r.get<std::uint32_t>();
    out.push_back(op);
  }
  r.done();
}

void write_counters(const RankFigures& figures,
                    std::span<const std::pair<std::uint32_t, NodeCountersSnapshot>> nodes,
                    std::span<const ObserverShare> shares, std::vector<std::uint8_t>& out) {
  static_assert(std::is_trivially_copyable_v<NodeCountersSnapshot>);
  Writer w(out);
  w.put(figures.max_lag_s);
  w.put(figures.late_ticks);
  w.put(figures.exchanged_bytes);
  w.put(figures.exchange_wall_s);
  w.put(figures.wall_s);
  w.put(static_cast<std::uint32_t>(nodes.size()));
  for (const auto& [node, counters] : nodes) {
    w.put(node);
    w.bytes(&counters, sizeof counters);
  }
  w.put(static_cast<std::uint32_t>(shares.size()));
  for (const ObserverShare& share : shares) {
    w.put(static_cast<std::uint32_t>(share.key.size()));
    w.bytes(share.key.data(), share.key.size());
    w.put(static_cast<std::uint32_t>(share.bytes.size()));
    w.bytes(share.bytes.data(), share.bytes.size());
  }
}

void read_counters(std::span<const std::uint8_t> bytes, std::size_t rank, std::size_t nodes,
                   RankFigures& figures,
                   std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>>& out,
                   std::vector<ObserverShare>& shares) {
  Reader r(bytes, rank, "counters");
  figures.max_lag_s = r.get<double>();
  figures.late_ticks = r.get<std::uint64_t>();
  figures.exchanged_bytes = r.get<std::uint64_t>();
  figures.exchange_wall_s = r.get<double>();
  figures.wall_s = r.get<double>();
  const std::uint32_t n = r.count(4 + sizeof(NodeCountersSnapshot));
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t node = r.node(nodes);
    NodeCountersSnapshot c;
    std::memcpy(&c, bytes.data() + r.skip(sizeof c), sizeof c);
    out.emplace_back(node, c);
  }
  const std::uint32_t k = r.count(8);  // two lengths each
  for (std::uint32_t i = 0; i < k; ++i) {
    ObserverShare share;
    const std::uint32_t key_size = r.count(1);
    const auto* key = bytes.data() + r.skip(key_size);
    share.key.assign(reinterpret_cast<const char*>(key), key_size);
    const std::uint32_t size = r.count(1);
    const auto* data = bytes.data() + r.skip(size);
    share.bytes.assign(data, data + size);
    shares.push_back(std::move(share));
  }
  r.done();
}

}  // namespace rfsitl::engine
