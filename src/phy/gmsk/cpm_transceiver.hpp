#pragma once
/// What the GMSK and the GFSK transceiver share: a frame's symbols sent through
/// the CPM modulator (cpm_modulator.hpp) and a receiver that is handed every
/// sample. A PHY derives from it and adds its frame format (its start_frame
/// checks the payload, writes the symbols into symbols() and calls send()), its
/// settings and its figures (sensitivity, decode latency).
///
/// Receiver: a class with push(std::span<const cf32>, RxHandler&), reset() and
/// busy() const, as Transceiver's receive, reset_receiver and rx_busy.
///
/// Not thread-safe, as every Transceiver: one node's object, one thread at a time.
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cpm_modulator.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy::gmsk {

template <class Receiver>
class CpmTransceiver : public Transceiver {
 public:
  std::size_t max_payload() const final { return max_payload_; }

  bool tx_busy() const final { return modulator_.samples_left() > 0; }

  std::size_t transmit(std::span<cf32> out) final { return modulator_.transmit(out); }

  void receive(std::span<const cf32> in, RxHandler& handler) final { receiver_.push(in, handler); }

  void reset_receiver() final { receiver_.reset(); }

  bool rx_busy() const final { return receiver_.busy(); }

 protected:
  /// `max_frame_symbols`: the symbols of a frame with `max_payload` bytes;
  /// `name` names the PHY in the payload check's message; the receiver is
  /// built from `receiver_args`.
  template <class... ReceiverArgs>
  CpmTransceiver(const char* name, std::size_t max_payload, CpmModulator modulator,
                 std::size_t max_frame_symbols, ReceiverArgs&&... receiver_args)
      : name_(name),
        max_payload_(max_payload),
        modulator_(std::move(modulator)),
        symbols_(max_frame_symbols),
        receiver_(std::forward<ReceiverArgs>(receiver_args)...) {}

  /// Throws std::invalid_argument if a payload of `bytes` exceeds
  /// max_payload(): a precondition, but a cheap one to check, and symbols()
  /// is sized by it.
  void check_payload(std::size_t bytes) const {
    if (bytes > max_payload_) {
      throw std::invalid_argument(std::string(name_) + " payload of " + std::to_string(bytes) +
                                  " bytes exceeds max_payload_bytes " +
                                  std::to_string(max_payload_));
    }
  }

  /// Where start_frame writes a frame's symbols (room for the largest frame).
  std::span<std::int8_t> symbols() { return symbols_; }

  /// Starts sending the first `count` symbols of symbols(); returns the
  /// frame's samples.
  std::size_t send(std::size_t count) {
    return modulator_.start(std::span<const std::int8_t>(symbols_).first(count));
  }

  const CpmModulator& modulator() const { return modulator_; }

 private:
  const char* name_;
  std::size_t max_payload_;
  CpmModulator modulator_;
  std::vector<std::int8_t> symbols_;
  Receiver receiver_;
};

}  // namespace rfsitl::phy::gmsk
