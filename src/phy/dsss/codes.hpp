#pragma once
/// Binary spreading codes as ±1 chips: Barker-11, maximal-length sequences and
/// Gold code families. Pure functions; every result is deterministic.
///
/// Polynomials (p(x) = x^n + ... + 1; the LFSR recurrence is
/// s[k+n] = s[k] + sum_{x^i in p, 0<i<n} s[k+i] mod 2, started from s[0..n-1] = 1,0,...,0;
/// chip = +1 for bit 0 and -1 for bit 1):
///
///   n   length  m-sequence polynomial (first of the Gold preferred pair)  second of the pair
///   5     31    x^5 + x^2 + 1                                             x^5 + x^4 + x^3 + x^2 +
///   1 6     63    x^6 + x + 1                                               x^6 + x^5 + x^2 + x +
///   1 7    127    x^7 + x^3 + 1                                             x^7 + x^3 + x^2 + x +
///   1 8    255    x^8 + x^6 + x^5 + x^4 + 1                                 (none: 8 is divisible
///   by 4) 9    511    x^9 + x^4 + 1                                             x^9 + x^6 + x^4 +
///   x^3 + 1
///  10   1023    x^10 + x^3 + 1                                            x^10 + x^8 + x^3 + x^2 +
///  1
///
/// These are the classical preferred pairs (Gold 1967; Sarwate & Pursley, Proc.
/// IEEE 68(5), 1980); the unit tests check primitivity (period 2^n - 1) and the
/// three-valued cross-correlation {-1, -t(n), t(n) - 2}, t(n) = 1 + 2^floor((n+2)/2).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rfsitl::phy::dsss {

/// One chip of a code: +1 or -1.
using Chip = std::int8_t;

/// A named code; `name` is canonical (what code_by_name accepts and returns).
struct SpreadingCode {
  std::string name;
  std::vector<Chip> chips;
};

/// Barker-11 as used by IEEE 802.11b: +1 -1 +1 +1 -1 +1 +1 +1 -1 -1 -1.
std::vector<Chip> barker11();

/// The maximal-length sequence of degree n (length 2^n - 1) from the table above.
/// Precondition: 5 <= n <= 10, else std::invalid_argument.
std::vector<Chip> m_sequence(unsigned degree);

/// Members of the Gold family of degree n (length N = 2^n - 1, N + 2 members):
/// index k < N is u XOR (v cyclically advanced by k), index N is u, index N + 1 is v,
/// where (u, v) is the preferred pair above.
/// Precondition: n in {5, 6, 7, 9, 10}, index < N + 2, else std::invalid_argument.
std::vector<Chip> gold_code(unsigned degree, std::size_t index);

/// Number of members of the Gold family of degree n: 2^n + 1.
std::size_t gold_family_size(unsigned degree);

/// Parses "barker11", "mseq<N>" (N = 31, 63, ..., 1023) or "gold<N>[:k]"
/// (N = 31, 63, 127, 511, 1023; k defaults to 0). Throws std::invalid_argument
/// with a message naming the code and the accepted forms.
SpreadingCode code_by_name(std::string_view name);

/// Periodic cross-correlation sum_i a[i] b[(i + shift) mod N].
/// Precondition: a.size() == b.size() > 0.
int periodic_correlation(const std::vector<Chip>& a, const std::vector<Chip>& b, std::size_t shift);

/// Aperiodic autocorrelation sum_{i < N - shift} a[i] a[i + shift]. Precondition: shift < N.
int aperiodic_autocorrelation(const std::vector<Chip>& a, std::size_t shift);

}  // namespace rfsitl::phy::dsss
