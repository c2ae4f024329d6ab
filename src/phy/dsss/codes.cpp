#include "codes.hpp"

#include <array>
#include <charconv>
#include <stdexcept>

namespace rfsitl::phy::dsss {
namespace {

/// Exponents i (0 < i < n) of the terms x^i of a polynomial x^n + ... + 1.
struct Polynomial {
  unsigned degree;
  std::array<unsigned, 3> taps;
  unsigned tap_count;
};

// Indexed by degree - 5. See the table in codes.hpp.
constexpr std::array<Polynomial, 6> kMsequence = {{
    {5, {2, 0, 0}, 1},
    {6, {1, 0, 0}, 1},
    {7, {3, 0, 0}, 1},
    {8, {6, 5, 4}, 3},
    {9, {4, 0, 0}, 1},
    {10, {3, 0, 0}, 1},
}};
constexpr std::array<Polynomial, 6> kGoldSecond = {{
    {5, {4, 3, 2}, 3},
    {6, {5, 2, 1}, 3},
    {7, {3, 2, 1}, 3},
    {8, {0, 0, 0}, 0},  // no preferred pair exists for n divisible by 4
    {9, {6, 4, 3}, 3},
    {10, {8, 3, 2}, 3},
}};

void check_degree(unsigned degree) {
  if (degree < 5 || degree > 10) {
    throw std::invalid_argument("m-sequence degree " + std::to_string(degree) +
                                " is outside 5..10");
  }
}

/// The LFSR bits s[0..2^n - 2] of the recurrence with characteristic polynomial p.
std::vector<std::uint8_t> lfsr_bits(const Polynomial& p) {
  const std::size_t n = p.degree;
  const std::size_t length = (std::size_t{1} << n) - 1;
  std::vector<std::uint8_t> s(length + n, 0);
  s[0] = 1;
  for (std::size_t k = 0; k + n < s.size(); ++k) {
    std::uint8_t v = s[k];
    for (unsigned t = 0; t < p.tap_count; ++t) v ^= s[k + p.taps[t]];
    s[k + n] = v;
  }
  s.resize(length);
  return s;
}

Chip chip_of(std::uint8_t bit) {
  return bit != 0 ? Chip{-1} : Chip{1};
}

std::vector<Chip> chips_of(const std::vector<std::uint8_t>& bits) {
  std::vector<Chip> c(bits.size());
  for (std::size_t i = 0; i < bits.size(); ++i) c[i] = chip_of(bits[i]);
  return c;
}

/// Degree n with 2^n - 1 == length, or 0.
unsigned degree_of_length(std::size_t length) {
  for (unsigned n = 5; n <= 10; ++n) {
    if ((std::size_t{1} << n) - 1 == length) return n;
  }
  return 0;
}

bool parse_number(std::string_view text, std::size_t& value) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc{} && end == text.data() + text.size();
}

[[noreturn]] void bad_name(std::string_view name, const std::string& why) {
  throw std::invalid_argument("code '" + std::string(name) + "': " + why +
                              " (accepted: barker11, mseq<N> with N in 31, 63, 127, 255, 511, "
                              "1023, gold<N>[:k] with N in 31, 63, 127, 511, 1023)");
}

}  // namespace

std::vector<Chip> barker11() {
  return {1, -1, 1, 1, -1, 1, 1, 1, -1, -1, -1};
}

std::vector<Chip> m_sequence(unsigned degree) {
  check_degree(degree);
  return chips_of(lfsr_bits(kMsequence[degree - 5]));
}

std::size_t gold_family_size(unsigned degree) {
  return (std::size_t{1} << degree) + 1;
}

std::vector<Chip> gold_code(unsigned degree, std::size_t index) {
  check_degree(degree);
  if (kGoldSecond[degree - 5].tap_count == 0) {
    throw std::invalid_argument("no Gold family of degree " + std::to_string(degree) +
                                " (preferred pairs do not exist for degrees divisible by 4)");
  }
  const auto u = lfsr_bits(kMsequence[degree - 5]);
  const auto v = lfsr_bits(kGoldSecond[degree - 5]);
  const std::size_t n = u.size();
  if (index >= n + 2) {
    throw std::invalid_argument("Gold code index " + std::to_string(index) + " is outside 0.." +
                                std::to_string(n + 1));
  }
  if (index == n) return chips_of(u);
  if (index == n + 1) return chips_of(v);
  std::vector<std::uint8_t> g(n);
  for (std::size_t i = 0; i < n; ++i) g[i] = u[i] ^ v[(i + index) % n];
  return chips_of(g);
}

SpreadingCode code_by_name(std::string_view name) {
  if (name == "barker11") return {"barker11", barker11()};
  auto number_after = [&](std::string_view prefix, std::string_view rest, std::size_t& value) {
    if (!parse_number(rest, value))
      bad_name(name, "expected a length after '" + std::string(prefix) + "'");
  };
  if (name.starts_with("mseq")) {
    std::size_t length = 0;
    number_after("mseq", name.substr(4), length);
    const unsigned n = degree_of_length(length);
    if (n == 0) bad_name(name, "no m-sequence of length " + std::to_string(length));
    return {"mseq" + std::to_string(length), m_sequence(n)};
  }
  if (name.starts_with("gold")) {
    const std::string_view spec = name.substr(4);
    const std::size_t colon = spec.find(':');
    std::size_t length = 0;
    number_after("gold", spec.substr(0, colon), length);
    std::size_t index = 0;
    if (colon != std::string_view::npos && !parse_number(spec.substr(colon + 1), index)) {
      bad_name(name, "expected a family member index after ':'");
    }
    const unsigned n = degree_of_length(length);
    if (n == 0 || n == 8) bad_name(name, "no Gold family of length " + std::to_string(length));
    if (index >= gold_family_size(n)) {
      bad_name(name, "member index " + std::to_string(index) + " is outside 0.." +
                         std::to_string(gold_family_size(n) - 1));
    }
    return {"gold" + std::to_string(length) + ":" + std::to_string(index), gold_code(n, index)};
  }
  bad_name(name, "unknown code family");
}

int periodic_correlation(const std::vector<Chip>& a, const std::vector<Chip>& b,
                         std::size_t shift) {
  const std::size_t n = a.size();
  int sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += a[i] * b[(i + shift) % n];
  return sum;
}

int aperiodic_autocorrelation(const std::vector<Chip>& a, std::size_t shift) {
  int sum = 0;
  for (std::size_t i = 0; i + shift < a.size(); ++i) sum += a[i] * a[i + shift];
  return sum;
}

}  // namespace rfsitl::phy::dsss
