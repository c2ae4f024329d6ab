#pragma once
/// The adaptation step of the cognitive DSSS link: from what a receiver hears
/// while its own link is silent, choose the spreading code that maximizes its
/// despreader output SINR.
///
/// Model. Let w be the L chips of interference plus noise that fall into one
/// code period of the despreader, and R = E[w w^H] (L x L). A binary code s
/// (entries +-1, s^T s = L) despreads a unit-power wanted chip stream to
/// amplitude L and the interference to s^T w, so the output SINR is
///   SINR(s) = (s^T s)^2 / (s^T R s) = L^2 / (s^T R s),
/// and for codes of equal norm maximizing SINR is minimizing s^T R s. Over
/// real unit-norm signatures the optimum is the eigenvector of R's smallest
/// eigenvalue (the "min-eigenvalue" signature); over binary signatures the
/// problem is NP-hard in general and is what D. A. Pados, S. N. Batalama,
/// G. N. Karystinos, M. Gkizeli and colleagues (Florida Atlantic University /
/// SUNY Buffalo) studied as SINR-maximizing binary signature design, e.g.
///   G. N. Karystinos, D. A. Pados, "New bounds on the total squared correlation
///     and optimum design of DS-CDMA binary signature sets", IEEE Trans.
///     Commun., 2003;
///   G. N. Karystinos, D. A. Pados, "Rank-2-optimal adaptive design of binary
///     spreading codes", IEEE Trans. Inf. Theory, 2007;
///   K. Gao, S. N. Batalama, D. A. Pados, B. W. Suter, "Cognitive code-division
///     channelization", IEEE Trans. Wireless Commun., 2011: a secondary link
///     picks its code from the interference autocorrelation its receiver
///     measures and feeds the choice back to its transmitter, as we do.
/// (Titles and years as we recall them; we cite no page numbers.) We solve the
/// binary problem by exhaustive search over a finite candidate set (below),
/// which contains the current code, so a switch never lowers the SINR under the
/// estimated R.
///
/// Estimating R. The despreader's code period is not synchronized with an
/// interferer, so averaged over all alignments R is Toeplitz (wide-sense
/// stationary interference): R[i][j] = r[j - i] with the lags
///   r[k] = E[ w*[n] w[n + k] ],   k = 0 .. L-1,  r[-k] = conj(r[k]),
/// estimated from chip-rate samples as a sample mean over windows that start
/// every `stride` chips (stride > 1 trades estimation samples for speed: the
/// cost is L / stride complex products per chip). For a real code s,
///   s^T R s = L r[0] + 2 sum_{k=1}^{L-1} Re(r[k]) A_s(k),
/// A_s the aperiodic autocorrelation of s, so with A_s precomputed each
/// candidate costs O(L). A narrowband tone at frequency f gives r[k] = P e^{j2pi f k}
/// and s^T R s = P |S(f)|^2: the choice is the candidate with the deepest
/// spectral null at f. Another DSSS transmitter on code c with random data gives
/// r[k] = P A_c(k) / L: code c itself pays for its own sidelobes (the cost is
/// L P (1 + 1/F), F the merit factor), the best candidate has sidelobes anti-
/// correlated with c's. (The bigger harm of a strong same-code transmitter, that
/// it captures the code's acquisition, is avoided by any other code of the family.)
/// White noise gives r[k] = sigma^2 delta[k] and the same cost for every code:
/// the hysteresis of CodeSelector::choose keeps the current code then.
#include <cstddef>
#include <span>
#include <vector>

#include "codes.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss {

/// Running sums of the lag products w*[n] w[n+k] over `windows` window starts.
struct LagSums {
  std::vector<double> re;
  std::vector<double> im;
  std::size_t windows = 0;

  explicit LagSums(std::size_t length = 0) : re(length, 0.0), im(length, 0.0) {}
  /// Precondition: same length.
  void add(const LagSums& other);
  void clear();
};

/// r[k] = sums / windows (zeros if there are no windows).
std::vector<cf32> normalized_lags(const LagSums& sums);

/// Accumulates lag products over a continuous chip stream, in pieces of any size.
class LagAccumulator {
 public:
  /// Preconditions (else std::invalid_argument): length >= 1, stride >= 1.
  LagAccumulator(std::size_t length, std::size_t stride = 1);

  /// Appends chips contiguous with the previous ones.
  void push(std::span<const cf32> chips);
  /// The next chip does not follow the last one (a gap): no window spans it.
  void break_stream();
  /// The sums so far; take() also zeroes them (the stream history is kept).
  const LagSums& sums() const { return sums_; }
  LagSums take();

 private:
  std::size_t length_;
  std::size_t stride_;
  std::vector<cf32> buffer_;  // chips not yet past every window that needs them
  std::size_t next_start_ = 0;
  LagSums sums_;
};

/// The lags of a finite chip record (a window every `stride` chips).
std::vector<cf32> estimate_lags(std::span<const cf32> chips, std::size_t length,
                                std::size_t stride = 1);

/// The candidate codes for a default code, deterministic so that both ends of a
/// link derive the same list (the control field carries an index into it):
/// entry 0 is the default itself; then, for a default of length N = 2^n - 1
/// with a Gold family (n = 5, 6, 7, 9, 10), the members gold<N>:0, :1, ... in
/// order, skipping chip sequences already listed, up to max_count entries in all.
/// Barker-11 and mseq255 have no family: the list is the default alone.
std::vector<SpreadingCode> adaptation_candidates(const SpreadingCode& default_code,
                                                 std::size_t max_count);

/// Scores a fixed candidate set against an interference estimate.
class CodeSelector {
 public:
  /// Precondition (else std::invalid_argument): at least one code, all of the
  /// same nonzero length. Cost O(count * L^2) once (aperiodic autocorrelations).
  explicit CodeSelector(std::vector<std::vector<Chip>> candidates);

  std::size_t size() const { return codes_.size(); }
  std::size_t length() const { return codes_.front().size(); }
  const std::vector<Chip>& code(std::size_t index) const { return codes_.at(index); }

  /// s^T R s for candidate `index` and the Toeplitz R of `lags` (size L).
  double interference_power(std::size_t index, std::span<const cf32> lags) const;
  /// 10 log10(L^2 / s^T R s): output SINR for a unit-power chip stream.
  double sinr_db(std::size_t index, std::span<const cf32> lags) const;

  struct Choice {
    std::size_t index = 0;         ///< the chosen candidate
    double sinr_db = 0.0;          ///< its predicted output SINR
    double current_sinr_db = 0.0;  ///< the current candidate's
  };
  /// The candidate with the highest SINR, if it beats `current` by at least
  /// hysteresis_db; otherwise `current` (among equals the lowest index wins).
  Choice choose(std::span<const cf32> lags, std::size_t current, double hysteresis_db) const;

 private:
  std::vector<std::vector<Chip>> codes_;
  std::vector<std::vector<double>> sidelobes_;  // A_s(k), k = 1 .. L-1
};

}  // namespace rfsitl::phy::dsss
