#pragma once
/// The external-transceiver protocol: how a node whose transceiver lives in
/// another process (an `rfsitl node` child, a GNU Radio flowgraph, any program)
/// stays in lock-step with the emulator.
///
/// Transport: one AF_UNIX SOCK_SEQPACKET socket per emulator (message
/// boundaries kept, in order, reliable). Every message is a 32-byte MsgHeader,
/// then `count` complex samples (cf32, 8 bytes each), then `extra_bytes` bytes.
/// Both ends are on one machine, so fields are in host byte order.
///
/// Handshake: the external side sends kHello (extra = JSON
/// {"node_id": n, "role": "samples"|"transceiver", "program": "...",
/// optionally "exclusive": true}); the emulator answers kWelcome (extra = JSON
/// {"protocol": 1, "node_id": n, "sample_rate_hz": fs, "tick_samples": B,
/// "time_mode": "realtime"|"virtual", "phy": {...} for the transceiver role,
/// "tx_report": 1 for the samples role}) or kReject (extra = reason, UTF-8)
/// and closes. A hello for a node another process holds takes the node over
/// (that process is dropped: how a restarted one rejoins), unless it is
/// exclusive: then it is refused. The hub admits one hello at a time, so of
/// two exclusive hellos at the same instant one is refused. Fields added
/// after protocol 1 are optional both ways: older readers ignore them.
/// The hello is due within 2 s of connecting (each connection has
/// its own deadline); both JSON texts are read by handshake.hpp, which refuses
/// any number outside its field's range rather than converting it.
///
/// Role "samples" (GNU Radio blocks, any program that owns its net port): each
/// tick k the emulator sends kTick {tick = k, time = first sample of tick k,
/// count = samples received during tick k-1 (B, or 0 for the first tick after
/// joining)} and waits for kTx {tick = k, count <= B samples to transmit from
/// `time` on, extra = a TxReport (tx_report.hpp) if the welcome names
/// tx_report >= 1, else nothing}; fewer than B are zero-padded. One round trip
/// per tick.
///
/// Role "transceiver" (`rfsitl node`: the emulator keeps the net port and the
/// accounting, the process runs the PHY): two round trips per tick, mirroring
/// the in-process Transceiver calls exactly, so results are identical:
///   kTxRequest {tick, time, count = 0, flags kFlagStartFrame: extra = a
///   FrameStart then the payload} -> kTx {count = samples carrying signal,
///   flags kFlagTxBusy while the frame continues};
///   kRx {count = samples, flags kFlagResetReceiver} -> kRxResult {flags
///   kFlagRxBusy, extra = a sequence of DecodeRecord, payload bytes, then
///   symbol_count cf32 constellation points}.
///
/// Discovery (any time, claims nothing): a process sends kDiscover (extra =
/// JSON {"discovery": 1, "program": "..."}) instead of a hello; the emulator
/// answers kDiscovery (extra = JSON {"discovery": 1, "nodes": [{"node_id",
/// "label", "role", "sample_rate_hz", "tick_samples", "carrier_hz",
/// "time_mode", "claimed"}...]}, one per external node) and closes. The
/// discovery has its own version number so that the hello/welcome (protocol
/// 1, which older clients check strictly) stays as it was. A bad request is
/// answered with kReject like a bad hello, and counted the same way.
///
/// A side that does not answer within the emulator's timeout, or sends
/// anything unexpected, is disconnected; it may connect again with kHello.
#include <cstdint>
#include <type_traits>

namespace rfsitl::external {

inline constexpr std::uint32_t kMagic = 0x58534652;  // "RFSX" in little-endian memory
inline constexpr int kProtocolVersion = 1;
/// Version of the kDiscover / kDiscovery JSON, independent of kProtocolVersion.
inline constexpr int kDiscoveryVersion = 1;

enum class MsgType : std::uint16_t {
  kHello = 1,
  kWelcome = 2,
  kReject = 3,
  kTick = 4,
  kTx = 5,
  kTxRequest = 6,
  kRx = 7,
  kRxResult = 8,
  kDiscover = 9,    ///< which external nodes are there? (claims nothing)
  kDiscovery = 10,  ///< the answer: every external node and whether it is claimed
};

// Flag bits, meaning per message type.
inline constexpr std::uint16_t kFlagStartFrame = 1;     ///< kTxRequest: extra holds a frame
inline constexpr std::uint16_t kFlagTxBusy = 1;         ///< kTx: transmitter still busy after it
inline constexpr std::uint16_t kFlagResetReceiver = 1;  ///< kRx: reset the RX path first
inline constexpr std::uint16_t kFlagRxBusy = 1;         ///< kRxResult: RX path inside a frame

struct MsgHeader {
  std::uint32_t magic = kMagic;
  std::uint16_t type = 0;  ///< MsgType
  std::uint16_t flags = 0;
  std::uint64_t tick = 0;         ///< lock-step tick index k
  std::uint64_t time = 0;         ///< virtual time (samples) of the tick's first sample
  std::uint32_t count = 0;        ///< cf32 samples that follow
  std::uint32_t extra_bytes = 0;  ///< bytes after the samples
};
static_assert(sizeof(MsgHeader) == 32 && std::is_trivially_copyable_v<MsgHeader>);

/// kTxRequest extra, before the payload bytes.
struct FrameStart {
  std::uint32_t serial = 0;
  std::uint8_t src = 0;
  std::uint8_t dst = 0;
  std::uint16_t reserved = 0;
};
static_assert(sizeof(FrameStart) == 8);

/// kRxResult extra: one per decode attempt, each followed by payload_bytes
/// bytes and symbol_count constellation points (cf32, for monitors).
struct DecodeRecord {
  std::uint32_t serial = 0;
  std::uint8_t src = 0;
  std::uint8_t dst = 0;
  std::uint8_t header_valid = 0;
  std::uint8_t payload_valid = 0;
  float rssi_db = 0.0F;
  float evm_db = 0.0F;
  std::uint32_t payload_bytes = 0;
  std::uint32_t symbol_count = 0;
};
static_assert(sizeof(DecodeRecord) == 24);

/// Largest message either side sends or accepts (the socket's datagram limit
/// is the kernel's default send buffer, about 208 KiB). It bounds B for
/// external nodes at 16384 samples.
inline constexpr std::size_t kMaxMessageBytes = 200 * 1024;
inline constexpr std::uint32_t kMaxExternalTickSamples = 16384;

}  // namespace rfsitl::external
