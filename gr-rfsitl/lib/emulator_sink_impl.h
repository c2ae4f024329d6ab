#pragma once
#include <gnuradio/rfsitl/emulator_sink.h>

#include <atomic>
#include <memory>
#include <vector>

#include "emulator_connection.h"

namespace gr::rfsitl {

class emulator_sink_impl : public emulator_sink {
 public:
  emulator_sink_impl(const std::string& socket_path, int node_id, const std::string& len_tag_key,
                     double max_buffer_s);
  ~emulator_sink_impl() override;

  bool stop() override;
  int work(int noutput_items, gr_vector_const_void_star& input_items,
           gr_vector_void_star& output_items) override;

  std::uint64_t buffered() const override { return conn_->buffered(); }
  std::uint64_t samples_in() const override { return samples_in_; }

 private:
  void start_burst(const gr::tag_t& tag);

  const std::shared_ptr<emulator_connection> conn_;
  const pmt::pmt_t len_tag_key_;  // PMT_NIL: plain stream
  std::vector<gr::tag_t> tags_;
  std::uint64_t burst_remaining_ = 0;  // samples still missing from the current burst
  bool warned_big_burst_ = false;
  bool said_ended_ = false;
  std::atomic<std::uint64_t> samples_in_{0};
};

}  // namespace gr::rfsitl
