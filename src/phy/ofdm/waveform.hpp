#pragma once
/// OFDM symbols, training fields and whole PPDUs in the time domain
/// (IEEE 802.11-2016 17.3.2 - 17.3.5). Sample rate: 20 Msps in the standard; at
/// the emulator's sample rate fs the same samples represent fs (the numerology
/// scales with fs).
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "rates.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::ofdm {

inline constexpr unsigned kFftSize = 64;
inline constexpr unsigned kCyclicPrefix = 16;
inline constexpr unsigned kSymbolSamples = kFftSize + kCyclicPrefix;  // 80
inline constexpr unsigned kPreambleSamples = 320;                     // L-STF + L-LTF

/// Subcarrier index (-26..26, no DC) of each of the 48 data subcarriers, in mapping order.
const std::array<int, 48>& data_subcarriers();
/// Pilot subcarrier indices -21, -7, 7, 21 (in that order); their base values
/// 1, 1, 1, -1 (17.3.5.10) are multiplied by pilot_polarity(n).
const std::array<int, 4>& pilot_subcarriers();
/// Pilot polarity p_n for OFDM symbol n (SIGNAL is n = 0), period 127 (17.3.5.10).
int pilot_polarity(unsigned n);

/// L-STF and L-LTF frequency-domain values on subcarrier k (-32..31).
cf32 short_training_value(int k);
cf32 long_training_value(int k);

/// The 24 SIGNAL bits (17.3.4): RATE, reserved 0, LENGTH (12 bits, LSB first),
/// even parity, 6 zero tail bits. Precondition: length_bytes < 4096.
std::vector<std::uint8_t> signal_field_bits(const RateParams& rate, unsigned length_bytes);

/// Builds the whole PPDU for `psdu` (MAC frame including its FCS): L-STF, L-LTF,
/// SIGNAL and DATA, with the 17.3.2.5 window of one overlapping sample at field
/// boundaries when `windowed` (Annex I's time-domain values), otherwise plain
/// concatenated symbols. Output: 320 + 80 (1 + N_SYM) samples (+1 trailing
/// half-sample when windowed). Preconditions: psdu.size() in 1..4095, seed in 1..127.
std::vector<cf32> build_ppdu(std::span<const std::uint8_t> psdu, const RateParams& rate,
                             std::uint8_t scrambler_seed, bool windowed);

/// Number of DATA OFDM symbols for a PSDU of `length_bytes` at `rate`.
unsigned data_symbol_count(const RateParams& rate, unsigned length_bytes);

}  // namespace rfsitl::phy::ofdm
