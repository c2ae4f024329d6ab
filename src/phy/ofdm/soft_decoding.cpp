#include "soft_decoding.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "bit_pipeline.hpp"

namespace rfsitl::phy::ofdm {
namespace {

// ---------------------------------------------------------------- demapping

/// Max-log LLRs of the m Gray-coded bits carried by one axis (I or Q) of a
/// 17.3.5.8 constellation. Level k (0 = most negative) sits at
/// (2k - (2^m - 1)) * k_mod and carries the label gray(k) = k ^ (k >> 1), first
/// bit in the label's MSB: this reproduces Tables 17-14 ... 17-17 (e.g. 16-QAM
/// 00 -> -3, 01 -> -1, 11 -> +1, 10 -> +3).
/// The number of bits per axis is a template parameter so that every loop below
/// unrolls and the Gray labels become constants (this runs for every coded bit).
template <unsigned m>
void axis_llrs(float x, float k_mod, float inv_noise_var, float* out) {
  constexpr unsigned n_levels = 1U << m;
  std::array<float, n_levels> dist{};
  for (unsigned k = 0; k < n_levels; ++k) {
    const float level =
        static_cast<float>(2 * static_cast<int>(k) - static_cast<int>(n_levels - 1));
    const float d = x - level * k_mod;
    dist[k] = d * d;
  }
  for (unsigned j = 0; j < m; ++j) {
    const unsigned shift = m - 1 - j;
    float d0 = std::numeric_limits<float>::infinity();
    float d1 = d0;
    for (unsigned k = 0; k < n_levels; ++k) {
      const unsigned gray = k ^ (k >> 1U);
      if (((gray >> shift) & 1U) != 0) {
        d1 = std::min(d1, dist[k]);
      } else {
        d0 = std::min(d0, dist[k]);
      }
    }
    // The other axis adds the same distance to both hypotheses and cancels.
    out[j] = (d1 - d0) * inv_noise_var;
  }
}

// K_MOD = 1/sqrt(2), 1/sqrt(10), 1/sqrt(42): unit mean power (Table 17-11).
const float kQpsk = 1.0F / std::sqrt(2.0F);
const float k16Qam = 1.0F / std::sqrt(10.0F);
const float k64Qam = 1.0F / std::sqrt(42.0F);

/// demap_soft() without its checks, n_bpsc one of 1, 2, 4, 6.
void demap_point(cf32 point, unsigned n_bpsc, float inv, float* out) {
  switch (n_bpsc) {
    case 1:  // BPSK: the bit rides on I alone, Q is pure noise
      axis_llrs<1>(point.real(), 1.0F, inv, out);
      return;
    case 2:
      axis_llrs<1>(point.real(), kQpsk, inv, out);
      axis_llrs<1>(point.imag(), kQpsk, inv, out + 1);
      return;
    case 4:
      axis_llrs<2>(point.real(), k16Qam, inv, out);
      axis_llrs<2>(point.imag(), k16Qam, inv, out + 2);
      return;
    default:
      axis_llrs<3>(point.real(), k64Qam, inv, out);
      axis_llrs<3>(point.imag(), k64Qam, inv, out + 3);
      return;
  }
}

bool valid_bpsc(unsigned n_bpsc) {
  return n_bpsc == 1 || n_bpsc == 2 || n_bpsc == 4 || n_bpsc == 6;
}

// ------------------------------------------------------------- puncturing

/// 17.3.5.6 puncturing patterns over the rate-1/2 stream A0 B0 A1 B1 ...:
/// 1 = transmitted. R = 2/3 steals B1 of every 2 data bits (sends A0 B0 A1);
/// R = 3/4 steals B1 and A2 of every 3 (sends A0 B0 A1 B2).
std::span<const std::uint8_t> keep_pattern(CodeRate rate) {
  static constexpr std::uint8_t kHalf[] = {1, 1};
  static constexpr std::uint8_t kTwoThirds[] = {1, 1, 1, 0};
  static constexpr std::uint8_t kThreeQuarters[] = {1, 1, 1, 0, 0, 1};
  switch (rate) {
    case CodeRate::kHalf:
      return kHalf;
    case CodeRate::kTwoThirds:
      return kTwoThirds;
    case CodeRate::kThreeQuarters:
      return kThreeQuarters;
  }
  throw std::invalid_argument("depuncture: unknown code rate");
}

// ---------------------------------------------------------- interleaving

/// The interleaver permutation of the four clause-17 symbol sizes, computed once
/// from the transmit side's own definition so both directions always agree.
const std::vector<unsigned>* standard_permutation(unsigned n_cbps, unsigned n_bpsc) {
  static const std::array<std::vector<unsigned>, 4> kTables = {
      interleaver_permutation(48, 1), interleaver_permutation(96, 2),
      interleaver_permutation(192, 4), interleaver_permutation(288, 6)};
  if (n_cbps != 48 * n_bpsc) return nullptr;
  switch (n_bpsc) {
    case 1:
      return &kTables[0];
    case 2:
      return &kTables[1];
    case 4:
      return &kTables[2];
    case 6:
      return &kTables[3];
    default:
      return nullptr;
  }
}

}  // namespace

void demap_soft(cf32 point, unsigned n_bpsc, float noise_var, std::span<float> out) {
  if (out.size() != n_bpsc) throw std::invalid_argument("demap_soft: out.size() != n_bpsc");
  if (!(noise_var > 0.0F)) throw std::invalid_argument("demap_soft: noise_var must be > 0");
  if (!valid_bpsc(n_bpsc)) throw std::invalid_argument("demap_soft: n_bpsc must be 1, 2, 4 or 6");
  demap_point(point, n_bpsc, 1.0F / noise_var, out.data());
}

void demap_symbol(std::span<const cf32> points, std::span<const float> noise_var, unsigned n_bpsc,
                  std::span<float> out) {
  if (!valid_bpsc(n_bpsc)) throw std::invalid_argument("demap_symbol: n_bpsc must be 1, 2, 4 or 6");
  if (noise_var.size() != points.size() || out.size() != points.size() * n_bpsc) {
    throw std::invalid_argument("demap_symbol: sizes do not match");
  }
  for (std::size_t d = 0; d < points.size(); ++d) {
    if (!(noise_var[d] > 0.0F)) throw std::invalid_argument("demap_symbol: noise_var must be > 0");
    demap_point(points[d], n_bpsc, 1.0F / noise_var[d], out.data() + d * n_bpsc);
  }
}

void deinterleave_into(std::span<const float> in, unsigned n_bpsc, std::span<float> out) {
  const auto n_cbps = static_cast<unsigned>(in.size());
  if (out.size() != in.size()) throw std::invalid_argument("deinterleave: out.size() != in.size()");
  std::vector<unsigned> other;
  const std::vector<unsigned>* perm = standard_permutation(n_cbps, n_bpsc);
  if (perm == nullptr) {
    other = interleaver_permutation(n_cbps, n_bpsc);  // validates the sizes
    perm = &other;
  }
  // interleave() sent input k to position perm[k]; fetch it back from there.
  for (unsigned k = 0; k < n_cbps; ++k) out[k] = in[(*perm)[k]];
}

std::vector<float> deinterleave(std::span<const float> in, unsigned n_bpsc) {
  std::vector<float> out(in.size());
  deinterleave_into(in, n_bpsc, out);
  return out;
}

std::vector<float> depuncture(std::span<const float> in, CodeRate rate, std::size_t n_data_bits) {
  const std::span<const std::uint8_t> keep = keep_pattern(rate);
  const std::size_t period = keep.size();
  const std::size_t n_coded = 2 * n_data_bits;
  // The pattern repeats over the whole stream; a final partial period keeps the
  // positions of the period's start, as puncture() does.
  const std::size_t per_period = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1));
  std::size_t expected = n_coded / period * per_period;
  for (std::size_t k = 0; k < n_coded % period; ++k) expected += keep[k];
  if (in.size() != expected) {
    throw std::invalid_argument("depuncture: input length does not match rate and n_data_bits");
  }
  // Period by period, without a division per value: this runs once per frame
  // and receiver over every coded bit (at 20 Msps, a receiver's hot spot).
  std::vector<float> out(n_coded, 0.0F);  // stolen positions stay erasures
  std::size_t next = 0;
  for (std::size_t i = 0; i < n_coded; i += period) {
    const std::size_t n = std::min(period, n_coded - i);
    for (std::size_t k = 0; k < n; ++k) {
      if (keep[k] != 0) out[i + k] = in[next++];
    }
  }
  return out;
}

}  // namespace rfsitl::phy::ofdm
