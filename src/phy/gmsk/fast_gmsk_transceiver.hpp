#pragma once
/// rfsitl's own GMSK transceiver, written for speed: a receiver that hears only
/// noise costs a few operations per sample, and one inside a frame a matched
/// filter per symbol.
///
/// Frame: see frame_format.hpp (64-symbol periodic preamble, 32-symbol sync
/// word, 80-symbol header with src, dst, serial, length and CRC-16, payload with
/// CRC-32, 2 tail symbols; header and payload whitened). An 80-byte payload at
/// k = 2, L = 3 is 1704 samples.
///
/// Modulation: exact sampled CPM with h = 1/2 and a Gaussian frequency pulse
/// (cpm_modulator.hpp), unit amplitude, so unit mean power.
///
/// Reception: delay-and-correlate preamble detection, then a filter matched to
/// Laurent's principal pulse C0 and a sync-word correlator for timing and phase,
/// a carrier frequency estimate from preamble to sync word, then coherent
/// MSK-type decisions with a decision-directed phase loop (see
/// src/phy/gmsk/frame_receiver.hpp).
///
/// Measured (bench/fast_gmsk_bench.cpp; k = 2, BT = 0.5, L = 3): 10% PER for
/// 80-byte frames at 5.3 dB per-sample SNR (liquid-dsp's GMSK: 10.4 dB);
/// carrier offsets up to 0.008 cycles per symbol (0.004 cycles/sample at k = 2)
/// are followed. Limits: symbol
/// timing is the nearest sample, which is exact in the emulator (whole-sample
/// delays) and costs about 1 dB at the worst fractional delay (half a sample at
/// k = 2); timing is not tracked within a frame (no sample clock drift); a
/// frame that starts during another's payload is lost.
#include <cstddef>
#include <memory>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy {

struct FastGmskSettings {
  unsigned samples_per_symbol = 2;       ///< k: 2..8
  float bandwidth_time = 0.5F;           ///< BT of the Gaussian filter: 0.2..1
  unsigned filter_span_symbols = 3;      ///< L: frequency pulse length in symbols, 1..8
  std::size_t max_payload_bytes = 2048;  ///< 1..65535
};

/// Throws std::invalid_argument, naming the field, if a setting is out of range.
/// sensitivity_snr_db() is the measured per-sample SNR of 10% PER for 80-byte
/// frames at k = 2, BT = 0.5, L = 3 (5.3 dB), less 10 log10(k / 2) for larger k
/// (the energy per bit grows with k at equal per-sample SNR; measured: 2.2 dB
/// at k = 4, -0.7 dB at k = 8). Other BT and L are not corrected for (BT = 0.3
/// needs about 0.7 dB more).
std::unique_ptr<Transceiver> make_fast_gmsk_transceiver(const FastGmskSettings& settings);

}  // namespace rfsitl::phy
