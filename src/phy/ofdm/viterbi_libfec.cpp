// The libfec-based Viterbi decoder (make_libfec_viterbi_decoder): Debian's
// libfec viterbi27, kept as an independent reference for the built-in decoder
// of viterbi_simd.cpp.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <mutex>
#include <new>
#include <stdexcept>

#include "soft_decoding.hpp"

// fec.h has no C++ linkage guard.
extern "C" {
#include <fec.h>
}

namespace rfsitl::phy::ofdm {
namespace {

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

std::unique_ptr<ViterbiDecoder> make_libfec_viterbi_decoder() {
  return std::make_unique<FecViterbiDecoder>();
}

}  // namespace rfsitl::phy::ofdm
