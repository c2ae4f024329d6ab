#include "rfsitl/monitor/pcap_trace.hpp"

#include <gtest/gtest.h>

#include <pcap/pcap.h>
#include <unistd.h>
#include "frame_event_builder.hpp"
#include "rfsitl/common/build_version.hpp"
#include "temp_dir.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace rfsitl::monitor {
namespace {

namespace fs = std::filesystem;
using engine::FrameEvent;
using engine::FrameEventKind;
using engine::LossReason;

/// A temp directory for this file's tests.
class TempDir : public rfsitl::testing::TempDir {
 public:
  TempDir() : rfsitl::testing::TempDir("rfsitl-pcap-test") {}
};

// --- our own pcapng reader: blocks, options, comments -----------------------

std::uint16_t le16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | p[1] << 8);
}
std::uint32_t le32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
std::uint64_t le64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(le32(p)) | static_cast<std::uint64_t>(le32(p + 4)) << 32;
}

struct RawPacket {
  std::uint64_t ts = 0;  // in the interface's resolution
  std::vector<std::uint8_t> data;
  std::string comment;
};

struct RawFile {
  std::vector<std::uint32_t> block_types;
  std::string shb_comment;
  std::string shb_userappl;
  std::uint16_t link_type = 0;
  int tsresol = -1;
  std::vector<RawPacket> packets;
};

/// Options from `p` to `end`: code -> value (comments appended in order).
std::vector<std::pair<std::uint16_t, std::string>> parse_options(const std::uint8_t* p,
                                                                 const std::uint8_t* end) {
  std::vector<std::pair<std::uint16_t, std::string>> out;
  while (p + 4 <= end) {
    const std::uint16_t code = le16(p);
    const std::uint16_t len = le16(p + 2);
    if (code == 0) break;
    EXPECT_LE(p + 4 + len, end) << "option overruns its block";
    out.emplace_back(code, std::string(reinterpret_cast<const char*>(p + 4), len));
    p += 4 + ((len + 3U) & ~3U);
  }
  return out;
}

RawFile read_raw(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  RawFile f;
  std::size_t at = 0;
  while (at + 12 <= bytes.size()) {
    const std::uint8_t* b = bytes.data() + at;
    const std::uint32_t type = le32(b);
    const std::uint32_t len = le32(b + 4);
    EXPECT_EQ(len % 4, 0U);
    EXPECT_GE(len, 12U);
    if (len < 12 || at + len > bytes.size()) {
      ADD_FAILURE() << "truncated block at " << at;
      break;
    }
    EXPECT_EQ(le32(b + len - 4), len) << "trailing block length";
    f.block_types.push_back(type);
    const std::uint8_t* end = b + len - 4;
    if (type == 0x0A0D0D0A) {
      EXPECT_EQ(le32(b + 8), 0x1A2B3C4DU);
      EXPECT_EQ(le16(b + 12), 1);
      EXPECT_EQ(le16(b + 14), 0);
      for (const auto& [code, value] : parse_options(b + 24, end)) {
        if (code == 1) f.shb_comment = value;
        if (code == 4) f.shb_userappl = value;
      }
    } else if (type == 1) {
      f.link_type = le16(b + 8);
      for (const auto& [code, value] : parse_options(b + 16, end)) {
        if (code == 9 && value.size() == 1) f.tsresol = static_cast<std::uint8_t>(value[0]);
      }
    } else if (type == 6) {
      RawPacket p;
      EXPECT_EQ(le32(b + 8), 0U);  // interface 0
      p.ts = static_cast<std::uint64_t>(le32(b + 12)) << 32 | le32(b + 16);
      const std::uint32_t caplen = le32(b + 20);
      EXPECT_EQ(le32(b + 24), caplen);
      p.data.assign(b + 28, b + 28 + caplen);
      for (const auto& [code, value] : parse_options(b + 28 + ((caplen + 3U) & ~3U), end)) {
        if (code == 1) p.comment = value;
      }
      f.packets.push_back(std::move(p));
    }
    at += len;
  }
  EXPECT_EQ(at, bytes.size()) << "trailing bytes";
  return f;
}

// --- libpcap's view ---------------------------------------------------------

struct LibpcapPacket {
  std::int64_t sec = 0;
  std::int64_t nsec = 0;
  std::vector<std::uint8_t> data;
};

struct LibpcapFile {
  int datalink = -1;
  std::vector<LibpcapPacket> packets;
};

LibpcapFile read_libpcap(const std::string& path) {
  char err[PCAP_ERRBUF_SIZE] = {};
  pcap_t* p =
      pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, err);
  if (p == nullptr) throw std::runtime_error(std::string("libpcap: ") + err);
  LibpcapFile f;
  f.datalink = pcap_datalink(p);
  pcap_pkthdr* h = nullptr;
  const u_char* data = nullptr;
  int rc = 0;
  while ((rc = pcap_next_ex(p, &h, &data)) == 1) {
    EXPECT_EQ(h->caplen, h->len);
    f.packets.push_back(LibpcapPacket{h->ts.tv_sec, h->ts.tv_usec, {data, data + h->caplen}});
  }
  EXPECT_EQ(rc, PCAP_ERROR_BREAK) << pcap_geterr(p);  // end of file, no error
  pcap_close(p);
  return f;
}

// --- decoding our encapsulation --------------------------------------------

struct Decoded {
  std::uint32_t present = 0;
  std::uint64_t tsft = 0;
  std::uint8_t flags = 0xFF;
  std::optional<std::uint8_t> rate;
  std::optional<std::int8_t> signal;
  std::optional<std::int8_t> noise;
  std::vector<std::uint8_t> fc, addr1, addr2, addr3, llc, payload;
  std::uint16_t seq_ctrl = 0;
};

Decoded decode(const std::vector<std::uint8_t>& d) {
  Decoded x;
  EXPECT_GE(d.size(), 8U);
  EXPECT_EQ(d[0], 0);  // radiotap version
  const std::size_t rt_len = le16(d.data() + 2);
  x.present = le32(d.data() + 4);
  EXPECT_EQ(x.present & 0x80000000U, 0U) << "no extended bitmap";
  std::size_t at = 8;
  const auto align = [&](std::size_t a) { at = (at + a - 1) / a * a; };
  if (x.present & 1U) {
    align(8);
    x.tsft = le64(d.data() + at);
    at += 8;
  }
  if (x.present & 2U) x.flags = d[at++];
  if (x.present & 4U) x.rate = d[at++];
  EXPECT_EQ(x.present & 0x18U, 0U) << "no channel, no FHSS";
  if (x.present & 0x20U) x.signal = static_cast<std::int8_t>(d[at++]);
  if (x.present & 0x40U) x.noise = static_cast<std::int8_t>(d[at++]);
  EXPECT_EQ(x.present & ~0x67U, 0U) << "only TSFT, Flags, Rate, signal, noise";
  EXPECT_EQ(at, rt_len) << "radiotap length covers exactly the fields";
  const auto take = [&](std::size_t n) {
    std::vector<std::uint8_t> v(d.begin() + static_cast<std::ptrdiff_t>(at),
                                d.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
    return v;
  };
  EXPECT_GE(d.size(), rt_len + 24 + 8);
  x.fc = take(2);
  take(2);  // duration
  x.addr1 = take(6);
  x.addr2 = take(6);
  x.addr3 = take(6);
  x.seq_ctrl = le16(d.data() + at);
  at += 2;
  x.llc = take(8);
  x.payload = take(d.size() - at);
  return x;
}

std::vector<std::uint8_t> mac(NodeId id) {
  if (id == kBroadcastId) return {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  return {0x02, 0x00, 0x00, 0x00, 0x00, id};
}

FrameEvent event(FrameEventKind kind, SampleTime t, NodeId src, NodeId dst, NodeId node,
                 std::uint32_t serial, std::vector<std::uint8_t> payload = {1, 2, 3}) {
  return engine::testing::frame_event(kind, t, src, dst, node, serial, 0, std::move(payload));
}

std::int64_t wall_s() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

TEST(PcapTrace, EveryEventIsOneRadiotap80211PacketThatLibpcapReads) {
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("sub/run.pcapng");  // the parent directory is created
  s.sample_rate_hz = 2e6;
  s.noise_db = -100.0;

  std::vector<FrameEvent> events;
  const std::vector<std::uint8_t> hello = {'h', 'e', 'l', 'l', 'o', 0x00, 0xFF};
  events.push_back(event(FrameEventKind::kHandedIn, 2000, 1, 2, 1, 0, hello));
  auto tx = event(FrameEventKind::kTransmitted, 2500, 1, 2, 1, 0x00000123, hello);
  tx.length_samples = 1064;
  tx.snr_db = 20.4;
  events.push_back(tx);
  auto rx = event(FrameEventKind::kReceived, 4000, 1, 2, 2, 0x00000123, hello);
  rx.snr_db = 20.4;
  events.push_back(rx);
  auto lost = event(FrameEventKind::kLost, 4250, 1, 2, 1, 0x01000003);
  lost.length_samples = 1064;
  lost.snr_db = 4.2;
  lost.reason = LossReason::kCollision;
  events.push_back(lost);
  auto bc = event(FrameEventKind::kDelivered, 3'000'001, 3, kBroadcastId, 3, 0x02000007);
  bc.phy = "ofdm";
  bc.rate_mbps = 12;
  bc.length_samples = 800;
  events.push_back(bc);
  events.push_back(event(FrameEventKind::kQueueDropped, 4300, 2, 1, 2, 0, {}));

  const std::int64_t before = wall_s();
  auto trace = make_pcap_trace(s);
  const std::int64_t after = wall_s();
  for (const auto& e : events) trace->on_frame_event(e);
  trace->flush();
  EXPECT_EQ(trace->events_written(), events.size());
  EXPECT_EQ(trace->files_dropped(), 0U);

  // Our own reading: blocks, options and comments.
  const RawFile raw = read_raw(s.path);
  ASSERT_GE(raw.block_types.size(), 2U);
  EXPECT_EQ(raw.block_types[0], 0x0A0D0D0AU);
  EXPECT_EQ(raw.block_types[1], 1U);
  EXPECT_EQ(raw.link_type, 127);
  EXPECT_EQ(raw.tsresol, 9);
  EXPECT_EQ(raw.shb_userappl, std::string("rfsitl ") + build_version());
  const auto pos = raw.shb_comment.find("epoch_offset_s=");
  ASSERT_NE(pos, std::string::npos) << raw.shb_comment;
  const std::int64_t offset = std::stoll(raw.shb_comment.substr(pos + 15));
  EXPECT_GE(offset, before);
  EXPECT_LE(offset, after);
  ASSERT_EQ(raw.packets.size(), events.size());
  EXPECT_EQ(raw.packets[0].comment,
            "rfsitl event=handed_in node=1 src=1 dst=2 serial=0x00000000 sample=2000 "
            "t=0.001000000 phy=gmsk");
  EXPECT_EQ(raw.packets[3].comment,
            "rfsitl event=lost node=1 src=1 dst=2 serial=0x01000003 snr_db=4.2 reason=collision "
            "sample=4250 t=0.002125000 air_samples=1064 phy=gmsk");
  EXPECT_EQ(raw.packets[2].comment.rfind("rfsitl event=received node=2 src=1 dst=2 ", 0), 0U)
      << raw.packets[2].comment;
  EXPECT_NE(raw.packets[4].comment.find("event=delivered node=3 src=3 dst=255"), std::string::npos);
  EXPECT_NE(raw.packets[4].comment.find("rate_mbps=12"), std::string::npos);

  // libpcap's reading: link type, timestamps, and the same bytes.
  const LibpcapFile lp = read_libpcap(s.path);
  EXPECT_EQ(lp.datalink, DLT_IEEE802_11_RADIO);
  ASSERT_EQ(lp.packets.size(), events.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    SCOPED_TRACE(i);
    const FrameEvent& e = events[i];
    const LibpcapPacket& p = lp.packets[i];
    // Virtual time at 2 MHz: 500 ns per sample, on top of the whole-second offset.
    const std::int64_t ns = e.time * 500;
    EXPECT_EQ(p.sec, offset + ns / 1'000'000'000);
    EXPECT_EQ(p.nsec, ns % 1'000'000'000);
    EXPECT_EQ(raw.packets[i].ts, static_cast<std::uint64_t>(offset) * 1'000'000'000ULL +
                                     static_cast<std::uint64_t>(ns));
    EXPECT_EQ(p.data, raw.packets[i].data);

    const Decoded d = decode(p.data);
    EXPECT_EQ(d.tsft, static_cast<std::uint64_t>(e.time / 2));  // microseconds
    EXPECT_EQ(d.flags, 0);
    EXPECT_EQ(d.rate.has_value(), e.phy == "ofdm");
    if (d.rate) {
      EXPECT_EQ(*d.rate, 24);  // 12 Mbit/s in 500 kb/s units
    }
    EXPECT_EQ(d.signal.has_value(), e.snr_db.has_value());
    if (d.signal) {
      EXPECT_EQ(*d.signal, static_cast<std::int8_t>(std::lround(*e.snr_db - 100.0)));
    }
    ASSERT_TRUE(d.noise.has_value());
    EXPECT_EQ(*d.noise, -100);
    EXPECT_EQ(d.fc, (std::vector<std::uint8_t>{0x08, 0x00}));  // data, no DS bits
    EXPECT_EQ(d.addr1, mac(e.dst));
    EXPECT_EQ(d.addr2, mac(e.src));
    EXPECT_EQ(d.addr3, (std::vector<std::uint8_t>{0x02, 0x72, 0x66, 0x73, 0x69, 0x6C}));
    EXPECT_EQ(d.seq_ctrl, (e.serial & 0xFFFU) << 4);
    EXPECT_EQ(d.llc, (std::vector<std::uint8_t>{0xAA, 0xAA, 0x03, 0, 0, 0, 0x88, 0xB5}));
    EXPECT_EQ(d.payload, e.payload);
  }
}

TEST(PcapTrace, AnIpNodesEthernetFrameKeepsItsAddressesAndEtherType) {
  // Node 1's IPv4 packet to node 2 (Ethernet dst, src, 0x0800, then IP):
  // the 802.11 addresses are the frame's, the SNAP header carries its
  // EtherType and the body is the IP packet, which Wireshark then decodes.
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("ip.pcapng");
  std::vector<std::uint8_t> frame = {0x02, 0, 0, 0, 0, 2, 0x02, 0, 0, 0, 0, 1, 0x08, 0x00};
  const std::vector<std::uint8_t> ip = {0x45, 0x00, 0x00, 0x14, 1, 2, 3,  4,  64, 1,
                                        0,    0,    10,   77,   0, 1, 10, 77, 0,  2};
  frame.insert(frame.end(), ip.begin(), ip.end());
  auto tx = event(FrameEventKind::kTransmitted, 100, 1, 2, 1, 0x00000005, frame);
  tx.frame_kind = FrameKind::kEthernet;
  auto trace = make_pcap_trace(s);
  trace->on_frame_event(tx);
  trace->flush();
  const LibpcapFile f = read_libpcap(s.path);
  ASSERT_EQ(f.packets.size(), 1U);
  const Decoded d = decode(f.packets[0].data);
  EXPECT_EQ(d.addr1, mac(2));
  EXPECT_EQ(d.addr2, mac(1));
  EXPECT_EQ(d.llc, (std::vector<std::uint8_t>{0xAA, 0xAA, 0x03, 0x00, 0x00, 0x00, 0x08, 0x00}));
  EXPECT_EQ(d.payload, ip);
  const RawFile raw = read_raw(s.path);
  ASSERT_EQ(raw.packets.size(), 1U);
  EXPECT_NE(raw.packets[0].comment.find(" kind=ethernet"), std::string::npos)
      << raw.packets[0].comment;
}

TEST(PcapTrace, TheMacsAckIsAn80211AckAndARepeatCarriesTheRetryFlag) {
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("mac.pcapng");
  auto ack = event(FrameEventKind::kTransmitted, 100, 2, 1, 2, 0x01000007, {1, 0, 5});
  ack.frame_kind = FrameKind::kMacControl;
  auto repeat = event(FrameEventKind::kTransmitted, 200, 1, 2, 1, 0x00000009, {7, 7});
  repeat.retry = true;
  auto trace = make_pcap_trace(s);
  trace->on_frame_event(ack);
  trace->on_frame_event(repeat);
  trace->flush();
  const LibpcapFile f = read_libpcap(s.path);
  ASSERT_EQ(f.packets.size(), 2U);
  // After the radiotap header (its length at bytes 2..3): frame control 0xD4
  // (control, subtype 13: ACK), duration, the receiver's address; nothing more.
  const std::vector<std::uint8_t>& a = f.packets[0].data;
  const std::size_t rt = a[2] | (a[3] << 8);
  ASSERT_EQ(a.size(), rt + 10);
  EXPECT_EQ(a[rt], 0xD4);
  EXPECT_EQ(a[rt + 1], 0x00);
  EXPECT_EQ(std::vector<std::uint8_t>(a.begin() + static_cast<std::ptrdiff_t>(rt + 4), a.end()),
            mac(1));
  const Decoded d = decode(f.packets[1].data);
  EXPECT_EQ(d.fc, (std::vector<std::uint8_t>{0x08, 0x08}));  // data, Retry
  const RawFile raw = read_raw(s.path);
  EXPECT_NE(raw.packets[0].comment.find(" kind=mac_control"), std::string::npos);
  EXPECT_NE(raw.packets[1].comment.find(" retry"), std::string::npos);
}

TEST(PcapTrace, SignalAndNoiseAreClampedToInt8) {
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("clamp.pcapng");
  s.noise_db = -300.0;  // no noise: 1e-30
  auto trace = make_pcap_trace(s);
  auto e = event(FrameEventKind::kTransmitted, 0, 1, 2, 1, 1);
  e.snr_db = 500.0;
  trace->on_frame_event(e);
  e.snr_db = 100.0;  // -200 dBm
  trace->on_frame_event(e);
  trace->flush();
  const LibpcapFile lp = read_libpcap(s.path);
  ASSERT_EQ(lp.packets.size(), 2U);
  const Decoded a = decode(lp.packets[0].data);
  const Decoded b = decode(lp.packets[1].data);
  EXPECT_EQ(a.signal, std::optional<std::int8_t>(127));
  EXPECT_EQ(a.noise, std::optional<std::int8_t>(-128));
  EXPECT_EQ(b.signal, std::optional<std::int8_t>(-128));
}

/// Serials written to one file, from the comments.
std::vector<std::uint32_t> serials_in(const std::string& path) {
  std::vector<std::uint32_t> out;
  for (const RawPacket& p : read_raw(path).packets) {
    const auto at = p.comment.find("serial=0x");
    EXPECT_NE(at, std::string::npos);
    out.push_back(static_cast<std::uint32_t>(std::stoul(p.comment.substr(at + 9, 8), nullptr, 16)));
  }
  return out;
}

TEST(PcapTrace, RotationKeepsAtMostMaxFilesWithTheNewestEvents) {
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("rot.pcapng");
  s.max_file_bytes = 2000;
  s.max_files = 3;
  {
    // Left over from an earlier run: must not pass for part of this one.
    std::ofstream(s.path + ".1") << "stale";
    std::ofstream(s.path + ".2") << "stale";
  }
  auto trace = make_pcap_trace(s);
  EXPECT_FALSE(fs::exists(s.path + ".1"));
  EXPECT_FALSE(fs::exists(s.path + ".2"));
  constexpr std::uint32_t kEvents = 100;
  for (std::uint32_t i = 0; i < kEvents; ++i) {
    // Same size every time (the time and the serial's width do not vary), so
    // that every full file holds the same number of events.
    auto e = event(FrameEventKind::kTransmitted, 1000, 1, 2, 1, i,
                   std::vector<std::uint8_t>(40, static_cast<std::uint8_t>(i)));
    trace->on_frame_event(e);
  }
  trace->flush();
  EXPECT_EQ(trace->events_written(), kEvents);

  ASSERT_TRUE(fs::exists(s.path));
  ASSERT_TRUE(fs::exists(s.path + ".1"));
  ASSERT_TRUE(fs::exists(s.path + ".2"));
  EXPECT_FALSE(fs::exists(s.path + ".3"));
  // Oldest first: FILE.2, FILE.1, FILE. Each is a complete pcapng of its own,
  // within the size bound, and together they hold the newest events in order.
  std::vector<std::uint32_t> kept;
  std::uint64_t per_file = 0;
  for (const std::string& f : {s.path + ".2", s.path + ".1", s.path}) {
    SCOPED_TRACE(f);
    EXPECT_LE(fs::file_size(f), s.max_file_bytes);
    const LibpcapFile lp = read_libpcap(f);
    EXPECT_EQ(lp.datalink, DLT_IEEE802_11_RADIO);
    const RawFile raw = read_raw(f);
    ASSERT_GE(raw.block_types.size(), 3U);
    EXPECT_EQ(raw.block_types[0], 0x0A0D0D0AU);
    EXPECT_EQ(raw.block_types[1], 1U);
    EXPECT_EQ(lp.packets.size(), raw.packets.size());
    const auto serials = serials_in(f);
    if (f != s.path) per_file = std::max<std::uint64_t>(per_file, serials.size());
    kept.insert(kept.end(), serials.begin(), serials.end());
  }
  ASSERT_FALSE(kept.empty());
  EXPECT_EQ(kept.back(), kEvents - 1);
  for (std::size_t i = 1; i < kept.size(); ++i) EXPECT_EQ(kept[i], kept[i - 1] + 1);
  EXPECT_LT(kept.size(), kEvents);
  // Every full file held per_file events: the dropped files held the oldest.
  ASSERT_GT(per_file, 0U);
  const std::uint64_t created = (kEvents + per_file - 1) / per_file;
  EXPECT_EQ(trace->files_dropped(), created - 3);
  EXPECT_EQ(kept.front(), (created - 3) * per_file);
  EXPECT_EQ(serials_in(s.path).size(), kEvents - (created - 1) * per_file);
}

TEST(PcapTrace, SingleFileRotationStartsOver) {
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("one.pcapng");
  s.max_file_bytes = 1000;
  s.max_files = 1;
  auto trace = make_pcap_trace(s);
  for (std::uint32_t i = 0; i < 30; ++i) {
    trace->on_frame_event(
        event(FrameEventKind::kTransmitted, i, 1, 2, 1, i, std::vector<std::uint8_t>(40, 7)));
  }
  trace->flush();
  EXPECT_FALSE(fs::exists(s.path + ".1"));
  EXPECT_GT(trace->files_dropped(), 0U);
  const auto serials = serials_in(s.path);
  ASSERT_FALSE(serials.empty());
  EXPECT_EQ(serials.back(), 29U);
  EXPECT_LE(fs::file_size(s.path), s.max_file_bytes);
}

TEST(PcapTrace, ConcurrentWritersLoseNothing) {
  TempDir dir;
  PcapTraceSettings s;
  s.path = dir.path("mt.pcapng");
  auto trace = make_pcap_trace(s);
  constexpr std::uint32_t kPerThread = 3000;
  std::atomic<bool> go{false};
  const auto writer = [&](std::uint32_t sender) {
    while (!go.load()) std::this_thread::yield();
    for (std::uint32_t i = 0; i < kPerThread; ++i) {
      const auto kind = sender == 0 ? FrameEventKind::kHandedIn : FrameEventKind::kTransmitted;
      trace->on_frame_event(event(kind, i, static_cast<NodeId>(sender + 1), 9,
                                  static_cast<NodeId>(sender + 1), sender << 24 | i,
                                  std::vector<std::uint8_t>(i % 50, 1)));
    }
  };
  std::thread a(writer, 0U);
  std::thread b(writer, 1U);
  std::thread reader([&] {
    while (!go.load()) std::this_thread::yield();
    for (int k = 0; k < 200; ++k) {
      (void)trace->events_written();
      trace->flush();
    }
  });
  go.store(true);
  a.join();
  b.join();
  reader.join();
  trace->flush();
  EXPECT_EQ(trace->events_written(), 2 * kPerThread);

  const LibpcapFile lp = read_libpcap(s.path);
  EXPECT_EQ(lp.packets.size(), 2 * kPerThread);
  // Each writer's events are all there, in its own order, intact.
  std::vector<std::uint32_t> next(2, 0);
  const RawFile raw = read_raw(s.path);
  ASSERT_EQ(raw.packets.size(), 2 * kPerThread);
  for (const RawPacket& p : raw.packets) {
    const auto at = p.comment.find("serial=0x");
    ASSERT_NE(at, std::string::npos);
    const auto serial =
        static_cast<std::uint32_t>(std::stoul(p.comment.substr(at + 9, 8), nullptr, 16));
    const std::uint32_t sender = serial >> 24;
    ASSERT_LT(sender, 2U);
    EXPECT_EQ(serial & 0xFFFFFFU, next[sender]);
    ++next[sender];
    const Decoded d = decode(p.data);
    EXPECT_EQ(d.payload.size(), (serial & 0xFFFFFFU) % 50);
    EXPECT_EQ(d.addr2, mac(static_cast<NodeId>(sender + 1)));
  }
  EXPECT_EQ(next[0], kPerThread);
  EXPECT_EQ(next[1], kPerThread);
}

TEST(PcapTrace, UnwritablePathThrowsNamingIt) {
  TempDir dir;
  const std::string blocker = dir.path("not-a-dir");
  std::ofstream(blocker) << "x";
  PcapTraceSettings s;
  s.path = blocker + "/run.pcapng";
  try {
    make_pcap_trace(s);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(s.path), std::string::npos) << e.what();
  }
}

TEST(PcapTrace, AFullDiskStopsTheTraceAndItsSummarySaysWhy) {
  TempDir dir;
  PcapTraceSettings ok;
  ok.path = dir.path("ok.pcapng");
  auto healthy = make_pcap_trace(ok);
  healthy->on_frame_event(event(FrameEventKind::kTransmitted, 0, 1, 2, 1, 1, {1, 2, 3}));
  healthy->flush();
  EXPECT_EQ(healthy->summary(), nlohmann::json({{"path", ok.path},
                                                {"events_written", 1},
                                                {"files_dropped", 0},
                                                {"stopped", false},
                                                {"error", nullptr}}));

  // /dev/full opens, then refuses every write with ENOSPC: a full disk.
  PcapTraceSettings full;
  full.path = "/dev/full";
  full.max_files = 1;  // nothing to rotate beside it
  auto trace = make_pcap_trace(full);
  constexpr std::uint32_t kEvents = 2000;  // far more than the write buffer holds
  for (std::uint32_t i = 0; i < kEvents; ++i) {
    trace->on_frame_event(
        event(FrameEventKind::kTransmitted, i, 1, 2, 1, i, std::vector<std::uint8_t>(200, 7)));
  }
  trace->flush();
  const nlohmann::json j = trace->summary();
  EXPECT_EQ(j.at("stopped"), true);
  EXPECT_EQ(j.at("error"), "write failed: No space left on device");
  EXPECT_LT(j.at("events_written").get<std::uint64_t>(), kEvents) << "it went on after the failure";
}

}  // namespace
}  // namespace rfsitl::monitor
