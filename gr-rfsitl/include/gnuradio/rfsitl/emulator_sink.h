#pragma once
/// The transmit half of an rfsitl external node (role "samples").
#include <gnuradio/rfsitl/api.h>
#include <gnuradio/sync_block.h>

#include <cstdint>
#include <memory>
#include <string>

namespace gr::rfsitl {

/// Buffers the samples a transmitter chain produces for node `node_id` until
/// the emulator_source of the same (socket_path, node_id) hands them to the
/// emulator, at most one tick per tick. Bursty transmitters work: the emulator
/// transmits zeros whenever the buffer is empty.
///
/// The buffer is bounded (`max_buffer_s` seconds at the emulator's sample
/// rate; 1 Msps assumed before the first join): when it is full the block
/// waits, which stalls the transmitter chain instead of dropping samples.
///
/// With `len_tag_key` set (e.g. "packet_len"), a tag of that key with value L
/// starts a burst of L samples that is released to the emulator only when all
/// of it is buffered, so a burst is never interrupted by zeros because the
/// transmitter chain delivered it in pieces. Untagged samples are released at
/// once. Set the tag's value in samples (blocks.tagged_stream_multiply_length
/// after a modulator that interpolates).
///
/// One emulator_sink per (socket_path, node_id) and process: make() throws
/// std::runtime_error for a second one, whose samples would interleave.
class RFSITL_API emulator_sink : virtual public gr::sync_block {
 public:
  using sptr = std::shared_ptr<emulator_sink>;

  /// \param socket_path  the emulator's external-node socket
  /// \param node_id      this node's id, 1..254
  /// \param len_tag_key  burst length tag key; empty: plain stream
  /// \param max_buffer_s buffer bound in seconds of samples
  static sptr make(const std::string& socket_path, int node_id, const std::string& len_tag_key = "",
                   double max_buffer_s = 0.5);

  /// Samples waiting to be transmitted (released or not).
  virtual std::uint64_t buffered() const = 0;
  /// Samples accepted from the input since the block was created.
  virtual std::uint64_t samples_in() const = 0;
};

}  // namespace gr::rfsitl
