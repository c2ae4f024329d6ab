#include "code_adaptation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rfsitl::phy::dsss {

void LagSums::add(const LagSums& other) {
  for (std::size_t k = 0; k < re.size() && k < other.re.size(); ++k) {
    re[k] += other.re[k];
    im[k] += other.im[k];
  }
  windows += other.windows;
}

void LagSums::clear() {
  std::fill(re.begin(), re.end(), 0.0);
  std::fill(im.begin(), im.end(), 0.0);
  windows = 0;
}

std::vector<cf32> normalized_lags(const LagSums& sums) {
  std::vector<cf32> r(sums.re.size());
  if (sums.windows == 0) return r;
  const double n = static_cast<double>(sums.windows);
  for (std::size_t k = 0; k < r.size(); ++k) {
    r[k] = cf32{static_cast<float>(sums.re[k] / n), static_cast<float>(sums.im[k] / n)};
  }
  return r;
}

LagAccumulator::LagAccumulator(std::size_t length, std::size_t stride)
    : length_(length), stride_(stride), sums_(length) {
  if (length == 0 || stride == 0) {
    throw std::invalid_argument("LagAccumulator: length and stride must be positive");
  }
}

void LagAccumulator::push(std::span<const cf32> chips) {
  buffer_.insert(buffer_.end(), chips.begin(), chips.end());
  while (next_start_ + length_ <= buffer_.size()) {
    const cf32* w = buffer_.data() + next_start_;
    const float a_re = w[0].real();
    const float a_im = -w[0].imag();  // conj(w[0])
    for (std::size_t k = 0; k < length_; ++k) {
      const float b_re = w[k].real();
      const float b_im = w[k].imag();
      sums_.re[k] += static_cast<double>(a_re * b_re - a_im * b_im);
      sums_.im[k] += static_cast<double>(a_re * b_im + a_im * b_re);
    }
    ++sums_.windows;
    next_start_ += stride_;
  }
  // Drop the chips no future window needs.
  const std::size_t drop = std::min(next_start_, buffer_.size());
  if (drop > 0) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(drop));
    next_start_ -= drop;
  }
}

void LagAccumulator::break_stream() {
  buffer_.clear();
  next_start_ = 0;
}

LagSums LagAccumulator::take() {
  LagSums out = sums_;
  sums_.clear();
  return out;
}

std::vector<cf32> estimate_lags(std::span<const cf32> chips, std::size_t length,
                                std::size_t stride) {
  LagAccumulator acc(length, stride);
  acc.push(chips);
  return normalized_lags(acc.sums());
}

std::vector<SpreadingCode> adaptation_candidates(const SpreadingCode& default_code,
                                                 std::size_t max_count) {
  std::vector<SpreadingCode> out;
  out.push_back(default_code);
  const std::size_t length = default_code.chips.size();
  unsigned degree = 0;
  for (unsigned n : {5U, 6U, 7U, 9U, 10U}) {
    if ((std::size_t{1} << n) - 1 == length) degree = n;
  }
  if (degree == 0 || default_code.name == "barker11") return out;
  const std::size_t family = gold_family_size(degree);
  for (std::size_t k = 0; k < family && out.size() < max_count; ++k) {
    std::vector<Chip> chips = gold_code(degree, k);
    const bool seen = std::any_of(out.begin(), out.end(),
                                  [&](const SpreadingCode& c) { return c.chips == chips; });
    if (seen) continue;
    out.push_back({"gold" + std::to_string(length) + ":" + std::to_string(k), std::move(chips)});
  }
  return out;
}

CodeSelector::CodeSelector(std::vector<std::vector<Chip>> candidates)
    : codes_(std::move(candidates)) {
  if (codes_.empty() || codes_.front().empty()) {
    throw std::invalid_argument("CodeSelector: needs at least one nonempty code");
  }
  const std::size_t length = codes_.front().size();
  sidelobes_.reserve(codes_.size());
  for (const auto& c : codes_) {
    if (c.size() != length) {
      throw std::invalid_argument("CodeSelector: codes of different lengths");
    }
    std::vector<double> a(length, 0.0);
    for (std::size_t k = 1; k < length; ++k) {
      int sum = 0;
      for (std::size_t i = 0; i + k < length; ++i) sum += c[i] * c[i + k];
      a[k] = sum;
    }
    sidelobes_.push_back(std::move(a));
  }
}

double CodeSelector::interference_power(std::size_t index, std::span<const cf32> lags) const {
  const std::size_t length = this->length();
  if (lags.size() != length) {
    throw std::invalid_argument("CodeSelector: expected " + std::to_string(length) + " lags, got " +
                                std::to_string(lags.size()));
  }
  const std::vector<double>& a = sidelobes_.at(index);
  double q = static_cast<double>(length) * static_cast<double>(lags[0].real());
  for (std::size_t k = 1; k < length; ++k) q += 2.0 * static_cast<double>(lags[k].real()) * a[k];
  return q;
}

double CodeSelector::sinr_db(std::size_t index, std::span<const cf32> lags) const {
  const double l = static_cast<double>(length());
  const double q = std::max(interference_power(index, lags), 1e-30);
  return 10.0 * std::log10(l * l / q);
}

CodeSelector::Choice CodeSelector::choose(std::span<const cf32> lags, std::size_t current,
                                          double hysteresis_db) const {
  Choice c;
  c.current_sinr_db = sinr_db(current, lags);
  std::size_t best = current;
  double best_db = c.current_sinr_db;
  for (std::size_t i = 0; i < codes_.size(); ++i) {
    const double s = sinr_db(i, lags);
    if (s > best_db) {
      best = i;
      best_db = s;
    }
  }
  if (best != current && best_db >= c.current_sinr_db + hysteresis_db) {
    c.index = best;
    c.sinr_db = best_db;
  } else {
    c.index = current;
    c.sinr_db = c.current_sinr_db;
  }
  return c;
}

}  // namespace rfsitl::phy::dsss
