#include "emulator_sink_impl.h"

#include <gnuradio/io_signature.h>

#include <algorithm>
#include <stdexcept>

#include "log_format.h"

namespace gr::rfsitl {

emulator_sink::sptr emulator_sink::make(const std::string& socket_path, int node_id,
                                        const std::string& len_tag_key, double max_buffer_s) {
  return gnuradio::make_block_sptr<emulator_sink_impl>(socket_path, node_id, len_tag_key,
                                                       max_buffer_s);
}

emulator_sink_impl::emulator_sink_impl(const std::string& socket_path, int node_id,
                                       const std::string& len_tag_key, double max_buffer_s)
    : gr::sync_block("emulator_sink", gr::io_signature::make(1, 1, sizeof(gr_complex)),
                     gr::io_signature::make(0, 0, 0)),
      conn_(emulator_connection::get(socket_path, node_id)),
      len_tag_key_(len_tag_key.empty() ? pmt::PMT_NIL : pmt::mp(len_tag_key)) {
  if (!(max_buffer_s > 0.0)) {
    throw std::invalid_argument("rfsitl emulator_sink: max_buffer_s must be > 0");
  }
  conn_->attach_sink(max_buffer_s);
}

emulator_sink_impl::~emulator_sink_impl() {
  conn_->detach_sink();
}

bool emulator_sink_impl::stop() {
  // A burst cut short by the end of the stream still goes out rather than
  // staying invisible in the buffer.
  if (burst_remaining_ > 0) {
    log_warn(*d_logger, "{}: stream ended {} samples before the end of a burst; sending it as is",
             conn_->label(), burst_remaining_);
    burst_remaining_ = 0;
  }
  conn_->release();
  return true;
}

void emulator_sink_impl::start_burst(const gr::tag_t& tag) {
  if (!pmt::is_integer(tag.value) && !pmt::is_uint64(tag.value)) {
    log_warn(*d_logger, "{}: ignoring {} tag that is not an integer", conn_->label(),
             pmt::symbol_to_string(tag.key));
    return;
  }
  const std::int64_t len = pmt::is_uint64(tag.value)
                               ? static_cast<std::int64_t>(pmt::to_uint64(tag.value))
                               : pmt::to_long(tag.value);
  if (burst_remaining_ > 0) {
    log_warn(*d_logger,
             "{}: new burst {} samples before the end of the previous one; sending that one",
             conn_->label(), burst_remaining_);
    burst_remaining_ = 0;
    conn_->release();
  }
  if (len <= 0) return;
  if (static_cast<std::uint64_t>(len) > conn_->capacity()) {
    // It could never be complete in the buffer; stream it instead.
    if (!warned_big_burst_) {
      warned_big_burst_ = true;
      log_warn(*d_logger,
               "{}: burst of {} samples exceeds the transmit buffer ({} samples); released as it "
               "arrives (raise max_buffer_s to keep bursts whole)",
               conn_->label(), len, conn_->capacity());
    }
    return;
  }
  burst_remaining_ = static_cast<std::uint64_t>(len);
}

int emulator_sink_impl::work(int noutput_items, gr_vector_const_void_star& input_items,
                             gr_vector_void_star& /*output_items*/) {
  const auto* in = static_cast<const gr_complex*>(input_items[0]);
  const auto n = static_cast<std::size_t>(noutput_items);
  const std::uint64_t base = nitems_read(0);
  tags_.clear();
  if (!pmt::is_null(len_tag_key_)) {
    get_tags_in_range(tags_, 0, base, base + n, len_tag_key_);
    std::sort(tags_.begin(), tags_.end(), gr::tag_t::offset_compare);
  }
  std::size_t i = 0;
  std::size_t t = 0;
  while (i < n) {
    while (t < tags_.size() && tags_[t].offset <= base + i) start_burst(tags_[t++]);
    // Copy up to the next tag, and inside a burst up to its end, so that the
    // release decision below holds for the whole segment.
    std::size_t end = t < tags_.size() ? static_cast<std::size_t>(tags_[t].offset - base) : n;
    if (burst_remaining_ > 0) end = std::min<std::size_t>(end, i + burst_remaining_);
    const std::size_t put = conn_->put_tx(in + i, end - i);
    if (put == 0) {
      // The source gave up for good: nothing will ever transmit these.
      if (!said_ended_) {
        said_ended_ = true;
        log_info(*d_logger, "{}: emulator_source has ended; transmit stream ends", conn_->label());
      }
      return i > 0 ? static_cast<int>(i) : WORK_DONE;
    }
    if (burst_remaining_ > 0) {
      burst_remaining_ -= put;
      if (burst_remaining_ == 0) conn_->release();
    } else {
      conn_->release();
    }
    i += put;
    samples_in_ += put;
  }
  return noutput_items;
}

}  // namespace gr::rfsitl
