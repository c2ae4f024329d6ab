#pragma once
/// Shared by the fast GMSK transceiver tests: a collecting RX handler, noise,
/// payloads, and helpers that put frames on the air and feed a receiver in chunks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <vector>

#include "phy/gmsk/fast_gmsk_transceiver.hpp"

namespace rfsitl::phy::fast_gmsk_test {

struct Event {
  FrameTag tag;
  std::vector<std::uint8_t> payload;
  bool header_valid = false;
  bool payload_valid = false;
  std::size_t fed = 0;  // samples fed up to the end of the reporting chunk
};

class Collector final : public RxHandler {
 public:
  void on_rx(const RxEvent& ev) override {
    events.push_back(Event{
        ev.tag, {ev.payload.begin(), ev.payload.end()}, ev.header_valid, ev.payload_valid, fed});
  }
  std::vector<Event> valid() const {
    std::vector<Event> v;
    std::copy_if(events.begin(), events.end(), std::back_inserter(v),
                 [](const Event& e) { return e.payload_valid; });
    return v;
  }
  std::vector<Event> events;
  std::size_t fed = 0;
};

inline void add_noise(std::span<cf32> x, double variance, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, static_cast<float>(std::sqrt(variance / 2.0)));
  for (cf32& v : x) v += cf32{g(rng), g(rng)};
}

inline std::vector<std::uint8_t> make_payload(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> p(n);
  for (auto& b : p) b = static_cast<std::uint8_t>(rng());
  return p;
}

inline std::unique_ptr<Transceiver> make(unsigned k = 2, std::size_t max_payload = 2048) {
  FastGmskSettings s;
  s.samples_per_symbol = k;
  s.max_payload_bytes = max_payload;
  return make_fast_gmsk_transceiver(s);
}

/// Writes the whole frame into air[start ...], rotated by a carrier phase.
inline std::size_t put_frame(Transceiver& tx, const FrameTag& tag,
                             std::span<const std::uint8_t> payload, std::vector<cf32>& air,
                             std::size_t start, float phase = 0.7F) {
  const std::size_t len = tx.start_frame(tag, payload);
  if (air.size() < start + len) air.resize(start + len);
  std::vector<cf32> f(len);
  EXPECT_EQ(tx.transmit(f), len);
  const cf32 rot = std::polar(1.0F, phase);
  for (std::size_t i = 0; i < len; ++i) air[start + i] += f[i] * rot;
  return len;
}

inline void receive_chunked(Transceiver& rx, std::span<const cf32> x, std::size_t chunk,
                            Collector& c) {
  for (std::size_t off = 0; off < x.size(); off += chunk) {
    const std::size_t len = std::min(chunk, x.size() - off);
    c.fed = off + len;
    rx.receive(x.subspan(off, len), c);
  }
}

/// Exactly one decode, valid, carrying `tag` and `payload`.
inline void expect_decoded(const Collector& c, const FrameTag& tag,
                           const std::vector<std::uint8_t>& payload) {
  ASSERT_EQ(c.events.size(), 1U);
  const Event& e = c.events.front();
  EXPECT_TRUE(e.header_valid);
  EXPECT_TRUE(e.payload_valid);
  EXPECT_EQ(e.tag.src, tag.src);
  EXPECT_EQ(e.tag.dst, tag.dst);
  EXPECT_EQ(e.tag.serial, tag.serial);
  EXPECT_EQ(e.payload, payload);
}

}  // namespace rfsitl::phy::fast_gmsk_test
