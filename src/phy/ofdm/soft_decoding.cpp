#include "rfsitl/phy/ofdm/soft_decoding.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "rfsitl/phy/ofdm/bit_pipeline.hpp"

// fec.h has no C++ linkage guard.
extern "C" {
#include <fec.h>
}

namespace rfsitl::phy::ofdm {
namespace {

// ---------------------------------------------------------------- demapping

/// Max-log LLRs of the m Gray-coded bits carried by one axis (I or Q) of a
/// 17.3.5.8 constellation. Level k (0 = most negative) sits at
/// (2k - (2^m - 1)) * k_mod and carries the label gray(k) = k ^ (k >> 1), first
/// bit in the label's MSB: this reproduces Tables 17-14 ... 17-17 (e.g. 16-QAM
/// 00 -> -3, 01 -> -1, 11 -> +1, 10 -> +3).
void axis_llrs(float x, unsigned m, float k_mod, float inv_noise_var, float* out) {
  const unsigned n_levels = 1U << m;
  std::array<float, 8> dist{};
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

// ---------------------------------------------------------------- Viterbi

constexpr std::size_t kMemory = 6;  // K - 1: tail length and state bits

// libfec soft symbols: 0 = certain '0', 255 = certain '1' (simd-viterbi(3)). No
// integer is on the midpoint; 128, Karn's erasure, costs 128 against a '0' branch
// and 127 against a '1', a bias of 1/255 of a certain symbol.
constexpr unsigned char kStrongZero = 0;
constexpr unsigned char kErasure = 128;
/// Distance from kErasure at which the mean |LLR| of a frame lands. The ML path of
/// max-log metrics does not change when every LLR is multiplied by the same
/// positive factor, so normalizing per frame loses nothing; 40 leaves headroom up
/// to ~3x the mean before saturating, and 1/40 of the mean as resolution.
constexpr float kMeanMagnitude = 40.0F;

void init_libfec_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    // libfec keeps the branch table, its parity table and the detected CPU mode in
    // unsynchronized globals that its first create call fills in; do that here,
    // once, so later decoders on other threads only read them.
    void* probe = create_viterbi27(1);
    if (probe == nullptr) throw std::bad_alloc();
    delete_viterbi27(probe);
    // libfec's encoder shifts new bits in at the LSB, so its taps are 802.11's
    // octal generators read backwards: 133 -> 0x6d (V27POLYA), 171 -> 0x4f
    // (V27POLYB). libfec expects symbols in polys[] order, i.e. A then B, which
    // is 802.11's order, with no inversion. These are libfec's defaults; setting
    // them says so and undoes any change by other code. (The table is global.)
    int polys[2] = {V27POLYA, V27POLYB};
    set_viterbi27_polynomial(polys);
  });
}

struct FecDeleter {
  void operator()(void* vp) const { delete_viterbi27(vp); }
};

class FecViterbiDecoder final : public ViterbiDecoder {
 public:
  FecViterbiDecoder() { init_libfec_once(); }

  std::vector<std::uint8_t> decode(std::span<const float> llr, std::size_t n_bits,
                                   bool terminated) override {
    if (llr.size() != 2 * n_bits) {
      throw std::invalid_argument("ViterbiDecoder::decode: need 2 * n_bits LLRs");
    }
    if (terminated && n_bits < kMemory) {
      throw std::invalid_argument("ViterbiDecoder::decode: a terminated block holds a 6-bit tail");
    }
    if (n_bits == 0) return {};

    // Trellis steps fed to libfec:
    // - a 6-step prefix of certain '0' pairs, which the encoder emits in state 0
    //   for zero inputs. libfec favours its start state by only 63 metric units (a
    //   quarter of one certain symbol). Every other path through the prefix -
    //   from another start state or leaving state 0 early - emits a '1' there and
    //   pays at least one certain symbol (255) on top.
    // - the n_bits data steps;
    // - unless terminated, 6 erasure steps. libfec's chainback must start from a
    //   named end state and does not expose the path metrics. After 6 steps
    //   without information every state reaches state 0, so chainback from 0
    //   retraces the survivor of the best end state. The erasure symbol is one
    //   unit off the exact midpoint (no integer is on it), which shifts the 64
    //   competing end states against each other by at most 10 metric units, an
    //   eighth of what one symbol of mean |LLR| weighs (2 * kMeanMagnitude): only
    //   near-ties can flip, and those are coin tosses anyway.
    const std::size_t suffix = terminated ? 0 : kMemory;
    const std::size_t steps = kMemory + n_bits + suffix;
    const std::size_t chain_bits = steps - kMemory;  // libfec treats the last 6 as tail
    reserve(chain_bits);

    syms_.resize(2 * steps);
    std::fill_n(syms_.begin(), 2 * kMemory, kStrongZero);
    quantize(llr, std::span(syms_).subspan(2 * kMemory, llr.size()));
    std::fill_n(syms_.begin() + static_cast<std::ptrdiff_t>(2 * (kMemory + n_bits)), 2 * suffix,
                kErasure);

    init_viterbi27(vp_.get(), 0);
    update_viterbi27_blk(vp_.get(), syms_.data(), static_cast<int>(steps));
    packed_.assign((chain_bits + 7) / 8, 0);
    chainback_viterbi27(vp_.get(), packed_.data(), static_cast<unsigned>(chain_bits), 0);

    // chainback packs MSB first (bit i -> byte i / 8, mask 0x80 >> i % 8). Skip
    // the prefix; a terminated block's tail was not returned and is zero.
    std::vector<std::uint8_t> bits(n_bits, 0);
    const std::size_t n_out = terminated ? n_bits - kMemory : n_bits;
    for (std::size_t i = 0; i < n_out; ++i) {
      const std::size_t c = kMemory + i;
      bits[i] = static_cast<std::uint8_t>((packed_[c / 8] >> (7 - c % 8)) & 1U);
    }
    return bits;
  }

 private:
  /// Makes the libfec instance hold `chain_bits` + 6 trellis steps.
  void reserve(std::size_t chain_bits) {
    if (vp_ && chain_bits <= capacity_) return;
    if (chain_bits > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2)) {
      throw std::length_error("ViterbiDecoder::decode: block too long for libfec");
    }
    // Grow geometrically so that a receiver decoding ever longer prefixes of a
    // frame does not reallocate on every call.
    const std::size_t len = std::max(chain_bits, capacity_ + capacity_ / 2);
    vp_.reset();  // free the old instance before allocating the larger one
    vp_.reset(create_viterbi27(static_cast<int>(len)));
    if (!vp_) {
      capacity_ = 0;
      throw std::bad_alloc();
    }
    capacity_ = len;
  }

  /// LLR -> libfec symbol: positive LLR (a likely '0') toward 0, erasure (0) to
  /// 128, scaled so that the mean finite nonzero |LLR| sits kMeanMagnitude away.
  static void quantize(std::span<const float> llr, std::span<unsigned char> out) {
    double sum = 0.0;
    std::size_t count = 0;
    for (float v : llr) {
      if (v != 0.0F && std::isfinite(v)) {
        sum += std::fabs(static_cast<double>(v));
        ++count;
      }
    }
    const float scale =
        count > 0 ? static_cast<float>(kMeanMagnitude * static_cast<double>(count) / sum) : 0.0F;
    for (std::size_t i = 0; i < llr.size(); ++i) {
      float s = static_cast<float>(kErasure) - llr[i] * scale;
      if (std::isnan(s)) s = static_cast<float>(kErasure);
      s = std::clamp(s, 0.0F, 255.0F);
      out[i] = static_cast<unsigned char>(std::lround(s));
    }
  }

  std::unique_ptr<void, FecDeleter> vp_;
  std::size_t capacity_ = 0;
  std::vector<unsigned char> syms_;
  std::vector<unsigned char> packed_;
};

}  // namespace

void demap_soft(cf32 point, unsigned n_bpsc, float noise_var, std::span<float> out) {
  if (out.size() != n_bpsc) throw std::invalid_argument("demap_soft: out.size() != n_bpsc");
  if (!(noise_var > 0.0F)) throw std::invalid_argument("demap_soft: noise_var must be > 0");
  const float inv = 1.0F / noise_var;
  switch (n_bpsc) {
    case 1:  // BPSK: the bit rides on I alone, Q is pure noise
      axis_llrs(point.real(), 1, 1.0F, inv, out.data());
      return;
    case 2:
    case 4:
    case 6: {
      // K_MOD = 1/sqrt(2), 1/sqrt(10), 1/sqrt(42): unit mean power (Table 17-11).
      const unsigned m = n_bpsc / 2;
      const float k_mod = m == 1 ? 1.0F / std::sqrt(2.0F)
                                 : (m == 2 ? 1.0F / std::sqrt(10.0F) : 1.0F / std::sqrt(42.0F));
      axis_llrs(point.real(), m, k_mod, inv, out.data());
      axis_llrs(point.imag(), m, k_mod, inv, out.data() + m);
      return;
    }
    default:
      throw std::invalid_argument("demap_soft: n_bpsc must be 1, 2, 4 or 6");
  }
}

std::vector<float> deinterleave(std::span<const float> in, unsigned n_bpsc) {
  const auto n_cbps = static_cast<unsigned>(in.size());
  std::vector<unsigned> other;
  const std::vector<unsigned>* perm = standard_permutation(n_cbps, n_bpsc);
  if (perm == nullptr) {
    other = interleaver_permutation(n_cbps, n_bpsc);  // validates the sizes
    perm = &other;
  }
  // interleave() sent input k to position perm[k]; fetch it back from there.
  std::vector<float> out(n_cbps);
  for (unsigned k = 0; k < n_cbps; ++k) out[k] = in[(*perm)[k]];
  return out;
}

std::vector<float> depuncture(std::span<const float> in, CodeRate rate, std::size_t n_data_bits) {
  const std::span<const std::uint8_t> keep = keep_pattern(rate);
  const std::size_t n_coded = 2 * n_data_bits;
  // The pattern repeats over the whole stream; a final partial period keeps the
  // positions of the period's start, as puncture() does.
  std::size_t expected = 0;
  for (std::size_t i = 0; i < n_coded; ++i) expected += keep[i % keep.size()];
  if (in.size() != expected) {
    throw std::invalid_argument("depuncture: input length does not match rate and n_data_bits");
  }
  std::vector<float> out(n_coded, 0.0F);  // stolen positions stay erasures
  std::size_t next = 0;
  for (std::size_t i = 0; i < n_coded; ++i) {
    if (keep[i % keep.size()] != 0) out[i] = in[next++];
  }
  return out;
}

std::unique_ptr<ViterbiDecoder> make_viterbi_decoder() {
  return std::make_unique<FecViterbiDecoder>();
}

}  // namespace rfsitl::phy::ofdm
