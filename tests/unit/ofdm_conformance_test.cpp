// Conformance of the 802.11a/g OFDM transmitter (IEEE 802.11-2016 clause 17)
// with the worked example of Annex I.1 (36 Mb/s, 100-octet PSDU, scrambler state
// 1011101), using the transcribed tables in tests/vectors/ieee80211a-annex-i
// (see its README.md; top level = 2016 edition, FCS 67 33 21 b6).
//
// Stages checked against published values (bits exactly, complex values to
// +-0.0011, i.e. the tables' 3-decimal rounding):
//   I-2   L-STF frequency domain (short_training_value)
//   I-3   L-STF one 64-sample period (build_ppdu, unwindowed, samples 0..63)
//   I-4   L-STF isolated, windowed (161 samples, from the unwindowed PPDU)
//   I-5   L-LTF frequency domain (long_training_value)
//   I-6   L-LTF isolated, windowed (161 samples, from the unwindowed PPDU)
//   I-7   SIGNAL bits (signal_field_bits)
//   I-8   SIGNAL coded bits (convolutional_encode)
//   I-9   SIGNAL interleaved bits (interleave, N_BPSC = 1)
//   I-10  SIGNAL BPSK points (map_point)
//   I-11  SIGNAL frequency domain incl. pilots (DFT of the PPDU's SIGNAL symbol)
//   I-12  SIGNAL isolated, windowed (81 samples, from the unwindowed PPDU)
//   I-13  DATA bits: SERVICE, PSDU (bytes_to_bits), tail, pad (data_symbol_count)
//   I-14  scrambler sequence for state 1011101 (scramble)
//   I-15  scrambled DATA bits with the tail reset (scramble)
//   I-16  all 1152 coded DATA bits at R = 3/4 (convolutional_encode + puncture)
//   I-17  first interleaver permutation (interleaver_permutation with s = 1)
//   I-18  second permutation (interleaver_permutation(192, 4) = j(i(k)))
//   I-19  DATA symbol 1 interleaved bits (interleave)
//   I-20  DATA symbol 1 16-QAM points (map_point) and its frequency domain with
//         pilots p_1 (DFT of the PPDU's first DATA symbol)
//   I-22 .. I-30  whole windowed PPDU, 881 samples (build_ppdu from psdu.hex)
// Also: the 1999/2007 Annex G packet (G.24, legacy FCS) from its own PSDU.
// Table I-1 (the PSDU) is the input; I-21 is not available (see README).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "phy/ofdm/bit_pipeline.hpp"
#include "phy/ofdm/rates.hpp"
#include "phy/ofdm/waveform.hpp"

namespace rfsitl::phy::ofdm {
namespace {

constexpr double kTol = 0.0011;       // tables print 3 decimals
constexpr std::uint8_t kSeed = 0x5D;  // 1011101 (x1..x7, a palindrome)
constexpr unsigned kLength = 100;

// ---- loader for the vector files -------------------------------------------

std::string vector_path(const std::string& name) {
  return std::string(RFSITL_SOURCE_DIR) + "/tests/vectors/ieee80211a-annex-i/" + name;
}

std::vector<std::string> read_lines(const std::string& name) {
  std::ifstream in(vector_path(name));
  if (!in) throw std::runtime_error("cannot open test vector " + vector_path(name));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

/// `*bits*.txt`: one 0/1 per line.
std::vector<std::uint8_t> read_bits(const std::string& name) {
  std::vector<std::uint8_t> bits;
  for (const std::string& l : read_lines(name)) bits.push_back(l == "1" ? 1 : 0);
  return bits;
}

/// Interleaver permutation files: one integer per line.
std::vector<unsigned> read_ints(const std::string& name) {
  std::vector<unsigned> v;
  for (const std::string& l : read_lines(name)) v.push_back(static_cast<unsigned>(std::stoul(l)));
  return v;
}

/// Time-domain and `*_symbols.txt` files: `re im` per line.
std::vector<std::complex<double>> read_complex(const std::string& name) {
  std::vector<std::complex<double>> v;
  for (const std::string& l : read_lines(name)) {
    std::istringstream s(l);
    double re = 0.0;
    double im = 0.0;
    s >> re >> im;
    v.emplace_back(re, im);
  }
  return v;
}

/// `*_freq.txt`: 64 lines `k re im`, returned indexed by k + 32.
std::vector<std::complex<double>> read_freq(const std::string& name) {
  std::vector<std::complex<double>> v(64);
  for (const std::string& l : read_lines(name)) {
    std::istringstream s(l);
    int k = 0;
    double re = 0.0;
    double im = 0.0;
    s >> k >> re >> im;
    v.at(static_cast<std::size_t>(k + 32)) = {re, im};
  }
  return v;
}

/// `psdu.hex`: one line of hex, octet 0 first.
std::vector<std::uint8_t> read_hex(const std::string& name) {
  const std::string hex = read_lines(name).at(0);
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    bytes.push_back(static_cast<std::uint8_t>(std::stoul(hex.substr(i, 2), nullptr, 16)));
  }
  return bytes;
}

// ---- helpers ------------------------------------------------------------

RateParams rate36() {
  return *rate_from_mbps(36);
}

template <typename A, typename B>
void expect_complex_near(const A& actual, const B& expected, const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  std::size_t bad = 0;
  double max_err = 0.0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double err = std::max(std::abs(actual[i].real() - expected[i].real()),
                                std::abs(actual[i].imag() - expected[i].imag()));
    max_err = std::max(max_err, err);
    if (err > kTol && ++bad <= 5) {  // report the first few, then only the count
      ADD_FAILURE() << what << " [" << i << "]: got " << actual[i] << ", table " << expected[i];
    }
  }
  EXPECT_EQ(bad, 0U) << what << ": values outside +-" << kTol << ", max error " << max_err;
}

/// 64-point DFT of x[first .. first + 63] (no scaling: the PPDU's symbols are
/// IFFT/64), returned indexed by subcarrier k + 32, k = -32..31.
std::vector<std::complex<double>> spectrum(const std::vector<cf32>& x, std::size_t first) {
  std::vector<std::complex<double>> out(64);
  for (int k = -32; k < 32; ++k) {
    std::complex<double> acc = 0.0;
    for (int n = 0; n < 64; ++n) {
      const double ph = -2.0 * std::numbers::pi * k * n / 64.0;
      acc += std::complex<double>(x[first + static_cast<std::size_t>(n)]) * std::polar(1.0, ph);
    }
    out[static_cast<std::size_t>(k + 32)] = acc;
  }
  return out;
}

/// A field as Annex I prints it on its own: samples x[first .. first+len-1] of
/// the unwindowed PPDU with the 17.3.2.5 window (first sample halved) plus one
/// trailing half-sample, the field's periodic continuation. That continuation
/// equals x[first + len - back] for any multiple `back` of the field's period
/// that stays inside the field (16 for L-STF, 128 for L-LTF, 64 for a symbol).
std::vector<cf32> isolated(const std::vector<cf32>& x, std::size_t first, std::size_t len,
                           std::size_t back) {
  std::vector<cf32> out(x.begin() + static_cast<std::ptrdiff_t>(first),
                        x.begin() + static_cast<std::ptrdiff_t>(first + len));
  out.front() *= 0.5F;
  out.push_back(0.5F * x[first + len - back]);
  return out;
}

/// SERVICE + PSDU + tail + pad (17.3.5.2, 17.3.5.3), as Table I-13 lists them.
std::vector<std::uint8_t> data_bits(const std::vector<std::uint8_t>& psdu, const RateParams& r) {
  const unsigned n_sym = data_symbol_count(r, static_cast<unsigned>(psdu.size()));
  std::vector<std::uint8_t> bits(16, 0);
  const std::vector<std::uint8_t> payload = bytes_to_bits(psdu);
  bits.insert(bits.end(), payload.begin(), payload.end());
  bits.resize(static_cast<std::size_t>(n_sym) * r.n_dbps, 0);  // tail and pad are zero
  return bits;
}

std::vector<std::uint8_t> scrambled(std::vector<std::uint8_t> bits, std::size_t psdu_bytes) {
  scramble(bits, kSeed);
  for (std::size_t i = 0; i < 6; ++i) bits[16 + 8 * psdu_bytes + i] = 0;  // tail reset
  return bits;
}

std::vector<cf32> map_all(const std::vector<std::uint8_t>& bits, unsigned n_bpsc) {
  std::vector<cf32> pts;
  for (std::size_t i = 0; i + n_bpsc <= bits.size(); i += n_bpsc) {
    pts.push_back(map_point(std::span(bits).subspan(i, n_bpsc), n_bpsc));
  }
  return pts;
}

std::vector<cf32> unwindowed_ppdu() {
  const std::vector<std::uint8_t> psdu = read_hex("psdu.hex");
  return build_ppdu(psdu, rate36(), kSeed, false);
}

// ---- tests ----------------------------------------------------------------

TEST(OfdmConformance, ShortTrainingFreqMatchesTableI2) {
  std::vector<cf32> s;
  for (int k = -32; k < 32; ++k) s.push_back(short_training_value(k));
  expect_complex_near(s, read_freq("lstf_freq.txt"), "I-2");
}

TEST(OfdmConformance, ShortTrainingPeriodMatchesTableI3) {
  const std::vector<cf32> x = unwindowed_ppdu();
  expect_complex_near(std::vector<cf32>(x.begin(), x.begin() + 64),
                      read_complex("lstf_time_one_period.txt"), "I-3");
}

TEST(OfdmConformance, ShortTrainingIsolatedMatchesTableI4) {
  expect_complex_near(isolated(unwindowed_ppdu(), 0, 160, 16),
                      read_complex("lstf_time_isolated.txt"), "I-4");
}

TEST(OfdmConformance, LongTrainingFreqMatchesTableI5) {
  std::vector<cf32> s;
  for (int k = -32; k < 32; ++k) s.push_back(long_training_value(k));
  expect_complex_near(s, read_freq("lltf_freq.txt"), "I-5");
}

TEST(OfdmConformance, LongTrainingIsolatedMatchesTableI6) {
  expect_complex_near(isolated(unwindowed_ppdu(), 160, 160, 128),
                      read_complex("lltf_time_isolated.txt"), "I-6");
}

TEST(OfdmConformance, SignalFieldBitsMatchTableI7) {
  EXPECT_EQ(signal_field_bits(rate36(), kLength), read_bits("signal_bits.txt"));
}

TEST(OfdmConformance, SignalCodedBitsMatchTableI8) {
  EXPECT_EQ(convolutional_encode(read_bits("signal_bits.txt")), read_bits("signal_coded_bits.txt"));
}

TEST(OfdmConformance, SignalInterleavedBitsMatchTableI9) {
  EXPECT_EQ(interleave(read_bits("signal_coded_bits.txt"), 1),
            read_bits("signal_interleaved_bits.txt"));
}

TEST(OfdmConformance, SignalBpskSymbolsMatchTableI10) {
  expect_complex_near(map_all(read_bits("signal_interleaved_bits.txt"), 1),
                      read_complex("signal_bpsk_symbols.txt"), "I-10");
}

TEST(OfdmConformance, SignalFreqMatchesTableI11) {
  expect_complex_near(spectrum(unwindowed_ppdu(), 320 + 16), read_freq("signal_freq.txt"), "I-11");
}

TEST(OfdmConformance, SignalTimeIsolatedMatchesTableI12) {
  expect_complex_near(isolated(unwindowed_ppdu(), 320, 80, 64),
                      read_complex("signal_time_isolated.txt"), "I-12");
}

TEST(OfdmConformance, DataBitsMatchTableI13) {
  EXPECT_EQ(data_bits(read_hex("psdu.hex"), rate36()), read_bits("data_bits.txt"));
}

TEST(OfdmConformance, ScramblerSequenceMatchesTableI14) {
  std::vector<std::uint8_t> zeros(127, 0);
  scramble(zeros, kSeed);
  EXPECT_EQ(zeros, read_bits("scrambler_sequence.txt"));
  // The seed file's string lists the state x1 first (bit 0 of the seed byte).
  const std::string s = read_lines("scrambler_seed.txt").at(0);
  ASSERT_EQ(s.size(), 7U);
  unsigned seed = 0;
  for (std::size_t i = 0; i < 7; ++i) seed |= static_cast<unsigned>(s[i] == '1') << i;
  EXPECT_EQ(seed, kSeed);
}

TEST(OfdmConformance, ScrambledBitsMatchTableI15) {
  EXPECT_EQ(scrambled(read_bits("data_bits.txt"), kLength), read_bits("data_scrambled_bits.txt"));
}

TEST(OfdmConformance, CodedDataBitsMatchTableI16) {
  const std::vector<std::uint8_t> coded = puncture(
      convolutional_encode(read_bits("data_scrambled_bits.txt")), CodeRate::kThreeQuarters);
  EXPECT_EQ(coded.size(), 1152U);
  EXPECT_EQ(coded, read_bits("data_coded_bits.txt"));
  const std::vector<std::uint8_t> sym1 = read_bits("data_sym1_coded_bits.txt");
  EXPECT_TRUE(std::equal(sym1.begin(), sym1.end(), coded.begin()));
}

TEST(OfdmConformance, FirstPermutationMatchesTableI17) {
  // With N_BPSC <= 2, s = 1 and the second permutation is the identity, so
  // interleaver_permutation(192, 1) is the first permutation i(k) of 17.3.5.7 alone.
  EXPECT_EQ(interleaver_permutation(192, 1), read_ints("interleaver_first_permutation.txt"));
}

TEST(OfdmConformance, SecondPermutationMatchesTableI18) {
  const std::vector<unsigned> first = read_ints("interleaver_first_permutation.txt");
  const std::vector<unsigned> second = read_ints("interleaver_second_permutation.txt");
  const std::vector<unsigned> perm = interleaver_permutation(192, 4);
  ASSERT_EQ(perm.size(), 192U);
  for (std::size_t k = 0; k < 192; ++k) EXPECT_EQ(perm[k], second.at(first.at(k))) << "k=" << k;
}

TEST(OfdmConformance, Symbol1InterleavedBitsMatchTableI19) {
  EXPECT_EQ(interleave(read_bits("data_sym1_coded_bits.txt"), 4),
            read_bits("data_sym1_interleaved_bits.txt"));
}

TEST(OfdmConformance, Symbol1MappedSymbolsMatchTableI20) {
  expect_complex_near(map_all(read_bits("data_sym1_interleaved_bits.txt"), 4),
                      read_complex("data_sym1_mapped_symbols.txt"), "I-20 points");
}

TEST(OfdmConformance, Symbol1FreqMatchesTableI20) {
  expect_complex_near(spectrum(unwindowed_ppdu(), 400 + 16), read_freq("data_sym1_freq.txt"),
                      "I-20 freq");
}

TEST(OfdmConformance, PacketTimeMatchesTablesI22ToI30) {
  const std::vector<cf32> x = build_ppdu(read_hex("psdu.hex"), rate36(), kSeed, true);
  ASSERT_EQ(x.size(), 881U);
  expect_complex_near(x, read_complex("packet_time.txt"), "I-22..I-30");
  struct Slice {
    const char* file;
    const char* table;
    std::size_t first;
  };
  const std::array<Slice, 9> slices = {{{"packet_lstf_time.txt", "I-22", 0},
                                        {"packet_lltf_time.txt", "I-23", 160},
                                        {"packet_signal_time.txt", "I-24", 320},
                                        {"packet_data_sym1_time.txt", "I-25", 400},
                                        {"packet_data_sym2_time.txt", "I-26", 480},
                                        {"packet_data_sym3_time.txt", "I-27", 560},
                                        {"packet_data_sym4_time.txt", "I-28", 640},
                                        {"packet_data_sym5_time.txt", "I-29", 720},
                                        {"packet_data_sym6_time.txt", "I-30", 800}}};
  for (const Slice& s : slices) {
    const std::vector<std::complex<double>> want = read_complex(s.file);
    const auto begin = x.begin() + static_cast<std::ptrdiff_t>(s.first);
    expect_complex_near(std::vector<cf32>(begin, begin + static_cast<std::ptrdiff_t>(want.size())),
                        want, s.table);
  }
}

TEST(OfdmConformance, LegacyPacketMatchesAnnexG24) {
  const std::vector<std::uint8_t> psdu = read_hex("legacy-1999-2007/psdu.hex");
  const std::vector<std::uint8_t> bits = data_bits(psdu, rate36());
  const std::vector<std::uint8_t> last144 = read_bits("legacy-1999-2007/data_bits_last144.txt");
  EXPECT_TRUE(std::equal(last144.begin(), last144.end(), bits.end() - 144)) << "G.14";
  const std::vector<std::uint8_t> scr = scrambled(bits, psdu.size());
  const std::vector<std::uint8_t> scr144 =
      read_bits("legacy-1999-2007/data_scrambled_bits_last144.txt");
  EXPECT_TRUE(std::equal(scr144.begin(), scr144.end(), scr.end() - 144)) << "G.17";
  expect_complex_near(build_ppdu(psdu, rate36(), kSeed, true),
                      read_complex("legacy-1999-2007/packet_time.txt"), "G.24");
}

}  // namespace
}  // namespace rfsitl::phy::ofdm
