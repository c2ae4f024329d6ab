#pragma once
#include <gnuradio/rfsitl/emulator_source.h>

#include <atomic>
#include <memory>
#include <vector>

#include "emulator_connection.h"

namespace gr::rfsitl {

class emulator_source_impl : public emulator_source {
 public:
  emulator_source_impl(const std::string& socket_path, int node_id, int timeout_ms,
                       int reconnect_ms);
  ~emulator_source_impl() override;

  bool start() override;
  bool stop() override;
  int work(int noutput_items, gr_vector_const_void_star& input_items,
           gr_vector_void_star& output_items) override;

  bool connected() const override { return connected_; }
  bool finished() const override { return finished_; }
  double sample_rate() const override { return sample_rate_hz_; }
  int tick_samples() const override { return tick_samples_; }
  std::uint64_t ticks() const override { return ticks_; }
  std::uint64_t joins() const override { return joins_; }
  std::uint64_t discontinuities() const override { return discontinuities_; }
  std::uint64_t tx_samples_sent() const override { return tx_samples_sent_; }

 private:
  /// Connects and handshakes, retrying for reconnect_ms. False: gave up.
  bool join();
  /// Waits for one tick and answers it. False: the connection ended.
  bool serve_tick();
  void leave(const std::string& why, bool expected = false);
  /// rx_time and rx_rate tags for the sample at `offset`.
  void add_time_tags(std::uint64_t offset, std::uint64_t virtual_time);

  const std::shared_ptr<emulator_connection> conn_;
  const int timeout_ms_;
  const int reconnect_ms_;

  std::vector<gr_complex> pending_;  // rx samples of the last tick not yet output
  std::size_t pending_pos_ = 0;
  bool pending_tag_ = false;        // pending_[0] starts a new contiguous segment
  std::uint64_t pending_time_ = 0;  // virtual time of pending_[0]
  std::vector<gr_complex> tx_;      // one tick of transmit samples
  bool tag_next_ = true;            // next rx samples start a new contiguous segment
  bool have_tick_ = false;
  std::uint64_t last_tick_ = 0;

  std::atomic<bool> connected_{false};
  std::atomic<bool> finished_{false};
  std::atomic<double> sample_rate_hz_{0.0};
  std::atomic<int> tick_samples_{0};
  std::atomic<std::uint64_t> ticks_{0};
  std::atomic<std::uint64_t> joins_{0};
  std::atomic<std::uint64_t> discontinuities_{0};
  std::atomic<std::uint64_t> tx_samples_sent_{0};
};

}  // namespace gr::rfsitl
