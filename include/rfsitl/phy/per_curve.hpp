#pragma once
/// A PHY's declared packet error rate curve: the probability that one frame is
/// lost in AWGN, as a function of the per-sample SNR and the payload size. It
/// is an estimate, declared once per PHY (PhyComponent::per_curve) so that
/// every estimate (`rfsitl links`, /api/links, a later Python module) is the
/// same; the engine never uses it: a frame's fate is always its decode.
///
/// SNR is the link matrix's and sensitivity_snr_db()'s: signal power over noise
/// power in the sample bandwidth fs, so Eb/N0 = SNR * (samples per bit).
///
/// The forms below are the textbook AWGN bit error rates with one constant per
/// PHY fitted to the PHY's measured curve (docs/per_vs_snr.csv, 500 frames of
/// 80 bytes per point, bench/per_sweep.cpp), and PER = 1 - (1 - BER)^bits over
/// the bits a frame's CRC covers (header and payload): bit errors are taken as
/// independent, which uncoded binary modulations in AWGN are. Losses of
/// acquisition (preamble, sync word) are left out: at the SNRs where frames
/// decode they are rare next to the bit errors of a long payload.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>

namespace rfsitl::phy {

/// PER in [0, 1] of a frame with `payload_bytes` payload bytes at per-sample
/// SNR `snr_db` (dB). Pure; any thread. NaN SNR gives 1 (no link).
using PerCurve = std::function<double(double snr_db, std::size_t payload_bytes)>;

/// Q(x) = P(N(0,1) > x).
inline double q_function(double x) {
  return 0.5 * std::erfc(x / std::sqrt(2.0));
}

/// 1 - (1 - ber)^bits without the rounding of 1 - ber near 1 (log1p, expm1).
inline double per_of_bits(double ber, double bits) {
  ber = std::clamp(ber, 0.0, 0.5);
  return std::clamp(-std::expm1(bits * std::log1p(-ber)), 0.0, 1.0);
}

/// Coherent binary detection of antipodal-like symbols:
/// BER = Q(sqrt(2 alpha Eb/N0)). alpha = 1 is ideal BPSK/MSK; Murota and
/// Hirade (IEEE Trans. Commun. 29(7), 1981) give alpha ~ 0.68 for GMSK with
/// BT = 0.25 and a simple detector; a better receiver approaches 1.
/// `overhead_bytes`: bytes the CRC covers besides the payload.
inline PerCurve coherent_binary_per(double alpha, double samples_per_bit,
                                    std::size_t overhead_bytes) {
  return [=](double snr_db, std::size_t payload_bytes) {
    if (std::isnan(snr_db)) return 1.0;
    const double eb_n0 = std::pow(10.0, snr_db / 10.0) * samples_per_bit;
    return per_of_bits(q_function(std::sqrt(2.0 * alpha * eb_n0)),
                       8.0 * static_cast<double>(payload_bytes + overhead_bytes));
  };
}

/// Differential or non-coherent binary detection: BER = 0.5 exp(-beta Eb/N0).
/// beta = 1 is DBPSK, beta = 1/2 non-coherent orthogonal BFSK (Proakis,
/// Digital Communications, 5th ed., 4.5-4 and 4.5-5).
inline PerCurve exponential_binary_per(double beta, double samples_per_bit,
                                       std::size_t overhead_bytes) {
  return [=](double snr_db, std::size_t payload_bytes) {
    if (std::isnan(snr_db)) return 1.0;
    const double eb_n0 = std::pow(10.0, snr_db / 10.0) * samples_per_bit;
    return per_of_bits(0.5 * std::exp(-beta * eb_n0),
                       8.0 * static_cast<double>(payload_bytes + overhead_bytes));
  };
}

/// A coded PHY's measured waterfall: PER of `ref_payload`-byte frames is the
/// logistic 1 / (1 + exp((snr_db - snr50_db) / width_db)) fitted to its
/// measurement, carried to other sizes through the bit error rate that would
/// give it over the frame's bits (`overhead_bytes` besides the payload).
inline PerCurve waterfall_per(double snr50_db, double width_db, std::size_t ref_payload,
                              std::size_t overhead_bytes) {
  return [=](double snr_db, std::size_t payload_bytes) {
    if (std::isnan(snr_db)) return 1.0;
    const double ref = 1.0 / (1.0 + std::exp(std::min(50.0, (snr_db - snr50_db) / width_db)));
    const double ref_bits = 8.0 * static_cast<double>(ref_payload + overhead_bytes);
    const double bits = 8.0 * static_cast<double>(payload_bytes + overhead_bytes);
    // 1 - (1 - ref)^(bits / ref_bits), in logs as per_of_bits.
    return std::clamp(-std::expm1(bits / ref_bits * std::log1p(-std::min(ref, 1.0 - 1e-16))), 0.0,
                      1.0);
  };
}

}  // namespace rfsitl::phy
