#include "rfsitl/monitor/pcap_trace.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <spdlog/spdlog.h>

#include "rfsitl/common/build_version.hpp"

namespace rfsitl::monitor {
namespace {

// pcapng block types and option codes (draft-ietf-opsawg-pcapng).
constexpr std::uint32_t kSectionHeaderBlock = 0x0A0D0D0A;
constexpr std::uint32_t kInterfaceDescriptionBlock = 0x00000001;
constexpr std::uint32_t kEnhancedPacketBlock = 0x00000006;
constexpr std::uint32_t kByteOrderMagic = 0x1A2B3C4D;
constexpr std::uint16_t kOptEndOfOpt = 0;
constexpr std::uint16_t kOptComment = 1;
constexpr std::uint16_t kShbUserAppl = 4;
constexpr std::uint16_t kIfName = 2;
constexpr std::uint16_t kIfDescription = 3;
constexpr std::uint16_t kIfTsResol = 9;
constexpr std::uint16_t kLinkTypeRadiotap = 127;  // LINKTYPE_IEEE802_11_RADIOTAP
constexpr std::uint32_t kSnapLen = 262144;

// Radiotap present bits.
constexpr std::uint32_t kRtTsft = 1U << 0;
constexpr std::uint32_t kRtFlags = 1U << 1;
constexpr std::uint32_t kRtRate = 1U << 2;
constexpr std::uint32_t kRtDbmSignal = 1U << 5;
constexpr std::uint32_t kRtDbmNoise = 1U << 6;

/// The 802.11 header's third address (the IBSS's BSSID): a constant,
/// locally administered unicast address, "\x02rfsil".
constexpr std::uint8_t kBssid[6] = {0x02, 0x72, 0x66, 0x73, 0x69, 0x6C};
/// An Ethernet header's length (destination, source, EtherType).
constexpr std::size_t kEthernetHeaderBytes = 14;

/// LLC/SNAP header carrying the IEEE local experimental EtherType 0x88B5.
constexpr std::uint8_t kLlcSnap[8] = {0xAA, 0xAA, 0x03, 0x00, 0x00, 0x00, 0x88, 0xB5};

/// Little-endian byte writer (pcapng lets the writer pick its byte order; we
/// always pick little-endian, as radiotap and 802.11 require anyway).
class Bytes {
 public:
  void u8(std::uint8_t v) { b_.push_back(v); }
  void u16(std::uint16_t v) {
    for (int i = 0; i < 2; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void raw(const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    b_.insert(b_.end(), c, c + n);
  }
  void pad_to(std::size_t alignment) {
    while (b_.size() % alignment != 0) b_.push_back(0);
  }
  void put_u32_at(std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b_[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void put_u16_at(std::size_t at, std::uint16_t v) {
    for (int i = 0; i < 2; ++i) b_[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  std::size_t size() const { return b_.size(); }
  void clear() { b_.clear(); }
  const std::vector<std::uint8_t>& data() const { return b_; }

  /// A pcapng option: code, length, value padded to 32 bits.
  void option(std::uint16_t code, const void* value, std::size_t length) {
    u16(code);
    u16(static_cast<std::uint16_t>(length));
    raw(value, length);
    pad_to(4);
  }
  void option(std::uint16_t code, const std::string& value) {
    option(code, value.data(), std::min<std::size_t>(value.size(), 0xFFFF));
  }
  void end_of_options() {
    u16(kOptEndOfOpt);
    u16(0);
  }

  /// Starts a block: type and a placeholder for its total length.
  std::size_t begin_block(std::uint32_t type) {
    const std::size_t at = b_.size();
    u32(type);
    u32(0);
    return at;
  }
  /// Ends a block started at `at`: trailing total length, both length fields set.
  void end_block(std::size_t at) {
    pad_to(4);
    const auto total = static_cast<std::uint32_t>(b_.size() - at + 4);
    u32(total);
    put_u32_at(at + 4, total);
  }

 private:
  std::vector<std::uint8_t> b_;
};

std::int8_t clamp_dbm(double db) {
  if (!std::isfinite(db)) return db > 0 ? std::int8_t{127} : std::int8_t{-128};
  return static_cast<std::int8_t>(std::clamp(std::lround(db), -128L, 127L));
}

void mac_of(NodeId id, std::uint8_t out[6]) {
  if (id == kBroadcastId) {
    std::fill_n(out, 6, std::uint8_t{0xFF});
    return;
  }
  const std::uint8_t mac[6] = {0x02, 0x00, 0x00, 0x00, 0x00, id};
  std::copy_n(mac, 6, out);
}

std::string comment_of(const engine::FrameEvent& e, double sample_rate_hz) {
  char buf[160];
  std::string s = "rfsitl event=";
  s += engine::frame_event_name(e.kind);
  std::snprintf(buf, sizeof buf, " node=%u src=%u dst=%u serial=0x%08x", e.node, e.src, e.dst,
                e.serial);
  s += buf;
  if (e.snr_db) {
    std::snprintf(buf, sizeof buf, " snr_db=%.1f", *e.snr_db);
    s += buf;
  }
  if (e.reason) {
    s += " reason=";
    s += engine::loss_reason_name(*e.reason);
  }
  std::snprintf(buf, sizeof buf, " sample=%lld t=%.9f", static_cast<long long>(e.time),
                static_cast<double>(e.time) / sample_rate_hz);
  s += buf;
  if (e.length_samples != 0) s += " air_samples=" + std::to_string(e.length_samples);
  if (!e.phy.empty()) s += " phy=" + e.phy;
  if (e.rate_mbps != 0) s += " rate_mbps=" + std::to_string(e.rate_mbps);
  if (e.frame_kind == FrameKind::kEthernet) s += " kind=ethernet";
  if (e.frame_kind == FrameKind::kMacControl) s += " kind=mac_control";
  if (e.retry) s += " retry";
  return s;
}

class PcapTraceImpl final : public PcapTrace {
 public:
  explicit PcapTraceImpl(const PcapTraceSettings& s)
      : settings_(s),
        max_files_(std::max(1U, s.max_files)),
        epoch_offset_s_(std::chrono::duration_cast<std::chrono::seconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count()) {
    if (!(settings_.sample_rate_hz > 0.0)) {
      throw std::runtime_error("pcap trace " + settings_.path + ": sample rate must be positive");
    }
    const std::filesystem::path p(settings_.path);
    if (p.has_parent_path()) {
      std::error_code ec;
      std::filesystem::create_directories(p.parent_path(), ec);  // fopen reports failures
    }
    // Rotated files of an earlier run would read as part of this one.
    for (unsigned k = 1; k < max_files_; ++k) {
      std::error_code ec;
      std::filesystem::remove(rotated_name(k), ec);
    }
    open_current();
  }

  ~PcapTraceImpl() override {
    std::lock_guard lock(mutex_);
    if (file_ != nullptr) std::fclose(file_);
  }

  void on_frame_event(const engine::FrameEvent& e) override {
    // Built outside the lock: only the file write is serialized.
    Bytes block;
    encode(e, block);
    append(block);
  }

  void on_retune(NodeId node, SampleTime time, double tx_hz, double rx_hz) override {
    Bytes block;
    encode_retune(node, time, tx_hz, rx_hz, block);
    append(block);
  }

  /// Writes one packet's block, rotating the file first when it would grow too big.
  void append(const Bytes& block) {
    std::lock_guard lock(mutex_);
    if (file_ == nullptr) return;  // a write failed earlier: the trace stopped
    if (packets_in_file_ > 0 && bytes_in_file_ + block.size() > settings_.max_file_bytes) {
      rotate();
      if (file_ == nullptr) return;
    }
    if (!write(block.data())) return;
    ++packets_in_file_;
    ++events_written_;
  }

  std::uint64_t events_written() const override {
    std::lock_guard lock(mutex_);
    return events_written_;
  }

  std::uint64_t files_dropped() const override {
    std::lock_guard lock(mutex_);
    return files_dropped_;
  }

  void flush() override {
    std::lock_guard lock(mutex_);
    if (file_ != nullptr && std::fflush(file_) != 0) fail("flush");
  }

  nlohmann::json summary() const override {
    std::lock_guard lock(mutex_);
    return {{"path", settings_.path},
            {"events_written", events_written_},
            {"files_dropped", files_dropped_},
            {"stopped", !error_.empty()},
            {"error", error_.empty() ? nlohmann::json(nullptr) : nlohmann::json(error_)}};
  }

 private:
  std::string rotated_name(unsigned k) const {
    return k == 0 ? settings_.path : settings_.path + "." + std::to_string(k);
  }

  /// Opens (truncates) the current file and writes its section header and
  /// interface description. Throws only from the constructor's first call.
  void open_current() {
    const bool first = !opened_once_;
    opened_once_ = true;
    file_ = std::fopen(settings_.path.c_str(), "wb");
    if (file_ == nullptr) {
      const std::string why = std::strerror(errno);
      if (first) throw std::runtime_error("cannot open pcap trace " + settings_.path + ": " + why);
      error_ = "cannot reopen after rotation: " + why;
      spdlog::error("pcap trace {}: {}; trace stopped", settings_.path, error_);
      return;
    }
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 18);
    bytes_in_file_ = 0;
    packets_in_file_ = 0;
    Bytes head;
    write_headers(head);
    if (!write(head.data()) && first) {
      throw std::runtime_error("cannot write pcap trace " + settings_.path);
    }
  }

  void write_headers(Bytes& b) const {
    // Section Header Block.
    std::size_t at = b.begin_block(kSectionHeaderBlock);
    b.u32(kByteOrderMagic);
    b.u16(1);                  // major version
    b.u16(0);                  // minor version
    b.u64(~std::uint64_t{0});  // section length: not given
    b.option(kShbUserAppl, std::string("rfsitl ") + build_version());
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "rfsitl frame-event trace; timestamp = epoch_offset_s + virtual time; "
                  "epoch_offset_s=%lld sample_rate_hz=%.17g noise_db=%.2f",
                  static_cast<long long>(epoch_offset_s_), settings_.sample_rate_hz,
                  settings_.noise_db);
    b.option(kOptComment, std::string(buf));
    b.end_of_options();
    b.end_block(at);
    // Interface Description Block.
    at = b.begin_block(kInterfaceDescriptionBlock);
    b.u16(kLinkTypeRadiotap);
    b.u16(0);  // reserved
    b.u32(kSnapLen);
    b.option(kIfName, std::string("rfsitl"));
    b.option(kIfDescription, std::string("rfsitl emulated channel: one packet per frame event"));
    const std::uint8_t tsresol = 9;  // nanoseconds
    b.option(kIfTsResol, &tsresol, 1);
    b.end_of_options();
    b.end_block(at);
  }

  /// Where an Enhanced Packet Block's parts are, as begin_packet() wrote them.
  struct PacketAt {
    std::size_t block;    // the block's start
    std::size_t lengths;  // its captured and original lengths, set by finish_packet()
    std::size_t packet;   // the packet's first byte
  };

  /// An Enhanced Packet Block's header, stamped with the virtual time `time`.
  PacketAt begin_packet(SampleTime time, Bytes& b) const {
    PacketAt at{b.begin_block(kEnhancedPacketBlock), 0, 0};
    b.u32(0);  // interface id
    // Multiplying first keeps these exact whenever fs divides 1e9 (or 1e6).
    const auto t = static_cast<long double>(std::max<SampleTime>(0, time));
    const auto fs = static_cast<long double>(settings_.sample_rate_hz);
    const auto ns = static_cast<std::uint64_t>(epoch_offset_s_) * 1'000'000'000ULL +
                    static_cast<std::uint64_t>(std::llround(t * 1e9L / fs));
    b.u32(static_cast<std::uint32_t>(ns >> 32));
    b.u32(static_cast<std::uint32_t>(ns & 0xFFFFFFFFU));
    at.lengths = b.size();
    b.u32(0);  // captured length, set below
    b.u32(0);  // original length
    at.packet = b.size();
    return at;
  }

  /// A retune as a packet of a bare radiotap header (no 802.11 frame: nothing
  /// went on the air), its comment saying where the radio now is.
  void encode_retune(NodeId node, SampleTime time, double tx_hz, double rx_hz, Bytes& b) const {
    const PacketAt at = begin_packet(time, b);
    b.u8(0);   // version
    b.u8(0);   // pad
    b.u16(8);  // length: the header alone
    b.u32(0);  // no fields present
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "rfsitl event=retune node=%u tx_hz=%.6f rx_hz=%.6f sample=%lld t=%.9f", node,
                  tx_hz, rx_hz, static_cast<long long>(time),
                  static_cast<double>(time) / settings_.sample_rate_hz);
    finish_packet(buf, b, at);
  }

  void encode(const engine::FrameEvent& e, Bytes& b) const {
    const PacketAt packet = begin_packet(e.time, b);
    const std::size_t packet_at = packet.packet;
    const auto t = static_cast<long double>(std::max<SampleTime>(0, e.time));
    const auto fs = static_cast<long double>(settings_.sample_rate_hz);

    // Radiotap header: version, pad, length, present; then the fields in bit
    // order, each aligned to its natural size from the header's start.
    std::uint32_t present = kRtTsft | kRtFlags | kRtDbmNoise;
    const bool has_rate = e.rate_mbps != 0;  // set for PHYs that declare a rate_mbps
    if (has_rate) present |= kRtRate;
    if (e.snr_db) present |= kRtDbmSignal;
    b.u8(0);  // version
    b.u8(0);  // pad
    const std::size_t rt_len_at = b.size();
    b.u16(0);
    b.u32(present);
    // TSFT (bit 0): u64 at offset 8, already 8-aligned.
    b.u64(static_cast<std::uint64_t>(std::floor(t * 1e6L / fs)));  // microseconds
    b.u8(0);  // Flags (bit 1): no FCS at the end, nothing else
    if (has_rate) b.u8(static_cast<std::uint8_t>(std::min(255U, e.rate_mbps * 2)));  // 500 kb/s
    if (e.snr_db) b.u8(static_cast<std::uint8_t>(clamp_dbm(*e.snr_db + settings_.noise_db)));
    b.u8(static_cast<std::uint8_t>(clamp_dbm(settings_.noise_db)));
    b.put_u16_at(rt_len_at, static_cast<std::uint16_t>(b.size() - packet_at));

    std::uint8_t mac[6];
    if (e.frame_kind == FrameKind::kMacControl) {
      // The MAC's ACK as 802.11's own (control type 1, subtype 13): frame
      // control, duration, receiver address. No FCS.
      b.u8(0xD4);
      b.u8(0x00);
      b.u16(0);
      mac_of(e.dst, mac);
      b.raw(mac, 6);
      finish_packet(comment_of(e, settings_.sample_rate_hz), b, packet);
      return;
    }
    // 802.11 data frame (type 2, subtype 0), ToDS = FromDS = 0 (IBSS):
    // addr1 = DA, addr2 = SA, addr3 = BSSID. No FCS.
    b.u8(0x08);                   // frame control: version 0, type data, subtype 0
    b.u8(e.retry ? 0x08 : 0x00);  // flags: Retry on a MAC's repeat
    b.u16(0);                     // duration
    // An Ethernet frame from an IP node keeps its own addresses and EtherType,
    // so Wireshark decodes the IP packet inside; anything else is an agent's
    // payload under the experimental EtherType.
    const bool ethernet =
        e.frame_kind == FrameKind::kEthernet && e.payload.size() >= kEthernetHeaderBytes;
    if (ethernet) {
      b.raw(e.payload.data(), 6);      // destination
      b.raw(e.payload.data() + 6, 6);  // source
    } else {
      mac_of(e.dst, mac);
      b.raw(mac, 6);
      mac_of(e.src, mac);
      b.raw(mac, 6);
    }
    b.raw(kBssid, 6);
    b.u16(static_cast<std::uint16_t>((e.serial & 0xFFFU) << 4));  // sequence number, fragment 0
    if (ethernet) {
      b.raw(kLlcSnap, 6);
      b.raw(e.payload.data() + 12, 2);  // the frame's EtherType
      b.raw(e.payload.data() + kEthernetHeaderBytes, e.payload.size() - kEthernetHeaderBytes);
    } else {
      b.raw(kLlcSnap, sizeof kLlcSnap);
      b.raw(e.payload.data(), e.payload.size());
    }
    finish_packet(comment_of(e, settings_.sample_rate_hz), b, packet);
  }

  /// The packet's lengths, padding and comment, and the block's end.
  void finish_packet(const std::string& comment, Bytes& b, const PacketAt& at) const {
    const auto packet_len = static_cast<std::uint32_t>(b.size() - at.packet);
    b.put_u32_at(at.lengths, packet_len);
    b.put_u32_at(at.lengths + 4, packet_len);
    b.pad_to(4);
    b.option(kOptComment, comment);
    b.end_of_options();
    b.end_block(at.block);
  }

  bool write(const std::vector<std::uint8_t>& bytes) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
      fail("write");
      return false;
    }
    bytes_in_file_ += bytes.size();
    return true;
  }

  // The trace ends here; the run goes on without it.
  void fail(const char* what) {
    error_ = std::string(what) + " failed: " + std::strerror(errno);
    spdlog::error("pcap trace {}: {}; trace stopped", settings_.path, error_);
    if (file_ != nullptr) std::fclose(file_);
    file_ = nullptr;
  }

  /// FILE.(max_files-2) -> FILE.(max_files-1), ..., FILE -> FILE.1; the oldest
  /// is deleted; a new FILE starts with its own headers.
  void rotate() {
    // Closing writes out the buffered tail: on a full disk that fails too.
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!closed) return fail("write");
    std::error_code ec;
    const std::string oldest = rotated_name(max_files_ - 1);
    if (std::filesystem::remove(oldest, ec)) ++files_dropped_;
    for (unsigned k = max_files_ - 1; k >= 1; --k) {
      if (!std::filesystem::exists(rotated_name(k - 1), ec)) continue;  // not that many yet
      std::filesystem::rename(rotated_name(k - 1), rotated_name(k), ec);
      if (ec) spdlog::warn("pcap trace: cannot rename {}: {}", rotated_name(k - 1), ec.message());
    }
    open_current();
  }

  const PcapTraceSettings settings_;
  const unsigned max_files_;
  const std::int64_t epoch_offset_s_;
  mutable std::mutex mutex_;
  std::FILE* file_ = nullptr;
  bool opened_once_ = false;
  std::uint64_t bytes_in_file_ = 0;
  std::uint64_t packets_in_file_ = 0;
  std::uint64_t events_written_ = 0;
  std::uint64_t files_dropped_ = 0;
  std::string error_;  ///< why the trace stopped early; "" while it is written
};

}  // namespace

std::unique_ptr<PcapTrace> make_pcap_trace(const PcapTraceSettings& settings) {
  return std::make_unique<PcapTraceImpl>(settings);
}

}  // namespace rfsitl::monitor
