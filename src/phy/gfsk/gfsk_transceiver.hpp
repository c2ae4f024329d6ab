#pragma once
/// A 2-GFSK transceiver modelled on the SiK telemetry radios of small UAVs
/// (3DR/RFD900/HM-TRP, firmware ArduPilot/SiK on the Si1000/Si4432 radio core).
///
/// What SiK does, from its register tables (radio_443x.c): GFSK with the
/// Si4432's Gaussian filter (BT = 0.5), a frequency deviation about equal to the
/// air data rate, i.e. modulation index h = 2 fd / Rb ~ 2.0 at every rate from
/// 2 to 128 kbit/s (1.65 at 192 and 1.27 at 250 kbit/s), data whitening on, a
/// 16-nibble (8-byte) 1010 preamble, sync word 0x2DD4 and a CRC-16. The
/// defaults below follow it: k = 8 (125 kbit/s at the emulator's 1 Msps, next to
/// SiK's 128 kbit/s column), h = 2, BT = 0.5, 8 preamble bytes, whitening on,
/// 255-byte payloads (the Si4432 packet length register is one byte).
///
/// Modulation: the CPM modulator GMSK uses (src/phy/gmsk/cpm_modulator.hpp) at
/// index h, with the Gaussian pulse truncated to gaussian_span_symbols(BT) or
/// the rectangular one at BT = 0, its phase computed in double; unit amplitude.
///
/// Frame (gfsk_frame.hpp), bits sent most significant first, bit 1 as the
/// upper tone (+fd): preamble (0xAA bytes), sync word 0x2DD4E395 (SiK's 0x2DD4
/// extended by 16 bits chosen for distance >= 13 from every whole-symbol
/// shift of itself and the preamble), the 10-byte header of the fast GMSK frame
/// (src, dst, serial u32 LE, length u16 LE, CRC-16) and the payload with its
/// own CRC-16; header and payload whitened with PN9. An 80-byte payload with
/// the defaults is 104 bytes = 832 symbols = 6672 samples (6.7 ms).
///
/// Receivers (the constant-envelope signal needs neither carrier phase nor
/// amplitude; both run on every sample, a few dozen operations each, noise or
/// not, and feed one sync search):
///   kEnergy        two-tone non-coherent detector: the symbol-long correlation
///                  of the input with each tone exp(+-j 2 pi fd t), decided by
///                  the larger |.|^2 (the optimum detector of orthogonal binary
///                  FSK with unknown phase when h is a whole number and BT = 0)
///   kDiscriminator FM discriminator: arg(y[n] y*[n-1]) of the input y after a
///                  short boxcar channel filter, summed over a symbol (limiter-
///                  discriminator with integrate-and-dump, what the Si4432's
///                  demodulator is); a carrier offset is removed as the mean
///                  output over the preamble.
/// Both keep a 48-bit history of hard decisions per sample phase; a frame is
/// found where the last 48 decisions (16 preamble bits and the sync word) match
/// with at most 3 errors, and its symbol timing is the sample, within half a
/// symbol of there, of largest soft correlation with those 48 bits. Unknown
/// timing and carrier phase are thus handled; carrier offsets up to 1% of the
/// symbol rate are tested (gfsk_transceiver_test.cpp).
///
/// RxEvent: rssi_db is the mean received power (signal plus noise, dB re unit
/// power) over header and payload; symbols are the soft decisions of header and
/// payload, real, scaled so that their mean magnitude is 1; evm_db is
/// 10 log10 of the mean of (|z| - 1)^2 over them (the spread of the detector
/// output, like an FSK error figure: about -SNR at the detector output).
///
/// Measured (bench/gfsk_per_bench.cpp, k = 8, 1000 80-byte frames per point),
/// Eb/N0 = per-sample SNR + 10 log10 k, against non-coherent orthogonal binary
/// FSK, Pb = 0.5 exp(-Eb / 2N0), BER 1e-3 at 10.94 dB:
///   energy detector, h = 1, BT = 0 (orthogonal tones): BER 1e-3 at 10.95 dB,
///   on the theory curve;
///   discriminator, h = 2, BT = 0.5 (SiK): 13.6 dB, 2.7 dB from it: an FM
///   discriminator is no optimum detector; its noise comes through a channel
///   filter wider than the symbol rate, near threshold the phase of the
///   filtered signal slips by 2 pi now and then (clicks), and the Gaussian
///   filter shortens isolated symbols' frequency excursion;
///   energy detector, h = 2, BT = 0.5: 13.3 dB (the Gaussian filter's
///   inter-symbol interference; at BT = 0 it is back on the theory curve).
/// 10% PER for 80-byte frames: 5.9 dB per-sample SNR with either receiver at
/// the defaults (Eb/N0 14.9 dB).
/// Cost on noise (one core of the shared 2-core development machine, 250-sample
/// ticks): energy detector about 11 ns per sample, discriminator 12 to 21 ns
/// (its arctangent), i.e. 50 to 90 receivers per core at 1 Msps.
#include <cstddef>
#include <memory>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy {

enum class GfskReceiver {
  kDiscriminator,  ///< FM discriminator, integrate and dump (SiK-like)
  kEnergy,         ///< two-tone non-coherent energy detector
};

struct GfskSettings {
  /// k: samples per symbol (= bit), 2..32; 8 gives 125 kbit/s at 1 Msps, 4 gives 250.
  unsigned samples_per_symbol = 8;
  /// h = 2 fd / Rb (fd the peak frequency deviation, Hz; Rb the bit rate), in
  /// (0, 2] and at most k - 1 (Carson's bandwidth (h + 1) Rb must fit in the
  /// sample rate). 2.0 is SiK's at 2..128 kbit/s.
  float modulation_index = 2.0F;
  /// BT of the Gaussian frequency filter, 0.2..1, or 0 for no shaping (plain
  /// continuous-phase FSK, rectangular frequency pulse). 0.5 is the Si4432's.
  float bandwidth_time = 0.5F;
  GfskReceiver receiver = GfskReceiver::kDiscriminator;
  bool whitening = true;                ///< PN9 over header and payload, as SiK
  std::size_t preamble_bytes = 8;       ///< 0xAA octets, 2..64 (SiK: 8)
  std::size_t max_payload_bytes = 255;  ///< 1..65535 (SiK: 255, a one-byte length)
};

/// Throws std::invalid_argument, naming the field, if a setting is out of range.
///
/// sensitivity_snr_db() is the per-sample SNR (dB) of 10% PER for 80-byte
/// frames measured at k = 8, h = 2, BT = 0.5 (5.9 dB, either receiver), less
/// 10 log10(k / 8) at other k (equal Eb/N0). Other h and BT are not corrected
/// for: at h = 1, BT = 0 the energy detector needs about 2 dB less.
std::unique_ptr<Transceiver> make_gfsk_transceiver(const GfskSettings& settings);

}  // namespace rfsitl::phy
