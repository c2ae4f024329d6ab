#pragma once
/// A packet trace of every frame event, in a file Wireshark opens: pcapng,
/// link type IEEE 802.11 + radiotap (127). Each event is one packet: radiotap
/// (TSFT = virtual time in microseconds, the 802.11 rate for OFDM frames,
/// antenna signal and noise in dBm-like units relative to unit TX power) and
/// an 802.11 data frame whose addresses are the node ids
/// (02:00:00:00:00:<id>) and whose body is the frame's payload; the event,
/// node, serial, SNR and outcome are in the packet's comment, e.g.
/// "rfsitl event=lost node=1 src=1 dst=2 serial=0x01000003 snr_db=4.2 reason=collision".
/// The encapsulation is documented in docs/traces.md. Size is bounded by
/// rotation: FILE, FILE.1, ... FILE.(max_files-1), oldest dropped. A write
/// that fails (a full disk) stops the trace, not the run: logged with the file
/// and the reason, and reported by summary().
#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "rfsitl/engine/engine_observer.hpp"

namespace rfsitl::monitor {

struct PcapTraceSettings {
  std::string path;                             ///< e.g. out/run.pcapng
  std::uint64_t max_file_bytes = 100ULL << 20;  ///< rotate beyond this
  unsigned max_files = 5;                       ///< files kept, the current one included
  double sample_rate_hz = 1e6;                  ///< converts virtual time to timestamps
  double noise_db = -120.0;                     ///< for radiotap's antenna-noise field
};

class PcapTrace : public engine::EngineObserver {
 public:
  /// Events written so far (all files), and files rotated away (deleted).
  virtual std::uint64_t events_written() const = 0;
  virtual std::uint64_t files_dropped() const = 0;
  /// Writes out buffered packets (also done on destruction).
  virtual void flush() = 0;
  /// For the run's summary: {"path", "events_written", "files_dropped",
  /// "stopped" (true once a write failed: the trace ends there), "error" (why,
  /// e.g. "write failed: No space left on device"; null while it is written)}.
  virtual nlohmann::json summary() const = 0;
};

/// Opens (truncates) settings.path. Throws std::runtime_error naming the path.
std::unique_ptr<PcapTrace> make_pcap_trace(const PcapTraceSettings& settings);

}  // namespace rfsitl::monitor
