#pragma once
#include <gnuradio/rfsitl/ubanc_framing.h>

#include <atomic>
#include <cstdint>
#include <vector>

namespace gr::rfsitl {

class ubanc_framing_impl : public ubanc_framing {
 public:
  ubanc_framing_impl(int node_id, int max_payload);

  std::uint64_t frames_to_radio() const override { return frames_to_radio_; }
  std::uint64_t frames_to_net() const override { return frames_to_net_; }
  std::uint64_t framing_errors() const override { return framing_errors_; }
  std::uint64_t frames_filtered() const override { return frames_filtered_; }

 private:
  void handle_net_in(const pmt::pmt_t& msg);
  void handle_radio_in(const pmt::pmt_t& msg);
  /// Emits every complete frame in buf_ and bounds what is left.
  void extract_frames();
  void framing_error(const std::string& what);

  const int node_id_;
  const std::size_t max_payload_;
  std::vector<std::uint8_t> buf_;  // bytes from the agent not yet framed
  std::size_t scanned_ = 0;        // buf_ prefix known to hold no terminator start
  bool discarding_ = false;        // inside an oversized frame, until its terminator

  std::atomic<std::uint64_t> frames_to_radio_{0};
  std::atomic<std::uint64_t> frames_to_net_{0};
  std::atomic<std::uint64_t> framing_errors_{0};
  std::atomic<std::uint64_t> frames_filtered_{0};
};

}  // namespace gr::rfsitl
