#pragma once
/// Private: the wire layout of each decoded message, written once and used both
/// ways. WireLayout<M>::fields(io, m) names m's fields in wire order (the base
/// fields stably sorted by element size, largest first, then the extension
/// fields in XML order); `io` is a PayloadWriter (serialize) or a PayloadReader
/// (deserialize). Multi-byte fields are little-endian, floats IEEE-754 binary32.
#include <algorithm>
#include <array>
#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#include "rfsitl/position/mavlink/messages.hpp"

namespace rfsitl::position::mavlink::detail {

template <class T>
concept WireScalar = std::integral<T> || std::same_as<T, float>;

/// Serializes into a 255-byte payload (the largest any message can have).
class PayloadWriter {
 public:
  template <WireScalar T>
  void operator()(const T& value) {
    using Bits = std::make_unsigned_t<std::conditional_t<std::same_as<T, float>, std::int32_t, T>>;
    const auto bits = std::bit_cast<Bits>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      bytes_[size_++] = static_cast<std::uint8_t>(bits >> (8 * i));
    }
  }

  template <WireScalar T, std::size_t N>
  void operator()(const std::array<T, N>& values) {
    for (const T& v : values) (*this)(v);
  }

  std::span<const std::uint8_t> bytes() const { return {bytes_.data(), size_}; }

 private:
  std::array<std::uint8_t, 255> bytes_{};
  std::size_t size_ = 0;
};

/// Deserializes from a payload as received: bytes past its end read as zero,
/// which is how a truncated MAVLink 2 payload is defined to be extended.
class PayloadReader {
 public:
  explicit PayloadReader(std::span<const std::uint8_t> payload) : payload_(payload) {}

  template <WireScalar T>
  void operator()(T& value) {
    using Bits = std::make_unsigned_t<std::conditional_t<std::same_as<T, float>, std::int32_t, T>>;
    Bits bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i, ++pos_) {
      if (pos_ < payload_.size()) bits = static_cast<Bits>(bits | Bits{payload_[pos_]} << (8 * i));
    }
    value = std::bit_cast<T>(bits);
  }

  template <WireScalar T, std::size_t N>
  void operator()(std::array<T, N>& values) {
    for (T& v : values) (*this)(v);
  }

 private:
  std::span<const std::uint8_t> payload_;
  std::size_t pos_ = 0;
};

template <class M>
struct WireLayout;

// M is the message type, const for writing. Sizes in the comments add up to
// the catalog's base/max lengths (checked by the unit tests).

template <>
struct WireLayout<Heartbeat> {  // 9 bytes
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.custom_mode);
    io(m.type);
    io(m.autopilot);
    io(m.base_mode);
    io(m.system_status);
    io(m.mavlink_version);
  }
};

template <>
struct WireLayout<GpsRawInt> {  // 30 bytes base, 52 with extensions
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.time_usec);
    io(m.lat_e7);
    io(m.lon_e7);
    io(m.alt_mm);
    io(m.eph);
    io(m.epv);
    io(m.vel_cm_s);
    io(m.cog_cdeg);
    io(m.fix_type);
    io(m.satellites_visible);
    io(m.alt_ellipsoid_mm);
    io(m.h_acc_mm);
    io(m.v_acc_mm);
    io(m.vel_acc_mm_s);
    io(m.hdg_acc_degE5);
    io(m.yaw_cdeg);
  }
};

template <>
struct WireLayout<Attitude> {  // 28 bytes
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.time_boot_ms);
    io(m.roll_rad);
    io(m.pitch_rad);
    io(m.yaw_rad);
    io(m.rollspeed_rad_s);
    io(m.pitchspeed_rad_s);
    io(m.yawspeed_rad_s);
  }
};

template <>
struct WireLayout<GlobalPositionInt> {  // 28 bytes
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.time_boot_ms);
    io(m.lat_e7);
    io(m.lon_e7);
    io(m.alt_mm);
    io(m.relative_alt_mm);
    io(m.vx_cm_s);
    io(m.vy_cm_s);
    io(m.vz_cm_s);
    io(m.hdg_cdeg);
  }
};

template <>
struct WireLayout<RequestDataStream> {  // 6 bytes
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.req_message_rate_hz);
    io(m.target_system);
    io(m.target_component);
    io(m.req_stream_id);
    io(m.start_stop);
  }
};

template <>
struct WireLayout<CommandLong> {  // 33 bytes
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.param);
    io(m.command);
    io(m.target_system);
    io(m.target_component);
    io(m.confirmation);
  }
};

template <>
struct WireLayout<CommandAck> {  // 3 bytes base, 10 with extensions
  template <class Io, class M>
  static void fields(Io& io, M& m) {
    io(m.command);
    io(m.result);
    io(m.progress);
    io(m.result_param2);
    io(m.target_system);
    io(m.target_component);
  }
};

}  // namespace rfsitl::position::mavlink::detail
