#include "phy/dsss/codes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfsitl::phy::dsss {
namespace {

int ones(const std::vector<Chip>& c) {
  return static_cast<int>(std::count(c.begin(), c.end(), Chip{-1}));
}

/// t(n) of Gold's bound: 1 + 2^floor((n + 2) / 2).
int gold_t(unsigned n) {
  return 1 + (1 << ((n + 2) / 2));
}

TEST(DsssCodes, Barker11IsThe80211bSequence) {
  const std::vector<Chip> expected = {1, -1, 1, 1, -1, 1, 1, 1, -1, -1, -1};
  EXPECT_EQ(barker11(), expected);
}

TEST(DsssCodes, Barker11AperiodicSidelobesAreAtMostOne) {
  const auto b = barker11();
  EXPECT_EQ(aperiodic_autocorrelation(b, 0), 11);
  for (std::size_t k = 1; k < b.size(); ++k) {
    EXPECT_LE(std::abs(aperiodic_autocorrelation(b, k)), 1) << "shift " << k;
  }
}

TEST(DsssCodes, MSequencesHaveTwoValuedPeriodicAutocorrelationAndBalance) {
  for (unsigned n = 5; n <= 10; ++n) {
    const auto m = m_sequence(n);
    const std::size_t length = (std::size_t{1} << n) - 1;
    ASSERT_EQ(m.size(), length);
    EXPECT_EQ(ones(m), 1 << (n - 1)) << "degree " << n << ": 2^(n-1) ones (chips -1)";
    EXPECT_EQ(periodic_correlation(m, m, 0), static_cast<int>(length));
    for (std::size_t k = 1; k < length; ++k) {
      ASSERT_EQ(periodic_correlation(m, m, k), -1) << "degree " << n << " shift " << k;
    }
  }
}

TEST(DsssCodes, MSequencePolynomialsArePrimitive) {
  // Periodic autocorrelation -1 at every nonzero shift already implies a period
  // of exactly 2^n - 1; check directly that no shorter period exists as well.
  for (unsigned n = 5; n <= 10; ++n) {
    const auto m = m_sequence(n);
    for (std::size_t p = 1; p < m.size(); ++p) {
      if (m.size() % p != 0) continue;
      bool periodic = true;
      for (std::size_t i = 0; i + p < m.size() && periodic; ++i) periodic = m[i] == m[i + p];
      EXPECT_FALSE(periodic) << "degree " << n << " repeats every " << p;
    }
  }
}

/// Every periodic cross-correlation between members `members` of the family
/// of degree n, at every shift, lies in {-1, -t(n), t(n) - 2}.
void expect_three_valued(unsigned n, const std::vector<std::size_t>& members) {
  const int t = gold_t(n);
  const std::set<int> allowed = {-1, -t, t - 2};
  std::vector<std::vector<Chip>> codes;
  for (const std::size_t i : members) codes.push_back(gold_code(n, i));
  std::set<int> seen;
  for (std::size_t a = 0; a < codes.size(); ++a) {
    for (std::size_t b = a; b < codes.size(); ++b) {
      for (std::size_t k = 0; k < codes[a].size(); ++k) {
        if (a == b && k == 0) continue;
        const int r = periodic_correlation(codes[a], codes[b], k);
        seen.insert(r);
        ASSERT_TRUE(allowed.count(r) == 1) << "degree " << n << " members " << members[a] << ", "
                                           << members[b] << " shift " << k << ": " << r;
      }
    }
  }
  EXPECT_EQ(seen, allowed) << "degree " << n << ": all three values occur";
}

TEST(DsssCodes, Gold31FamilyCrossCorrelationIsThreeValued) {
  std::vector<std::size_t> all(gold_family_size(5));
  std::iota(all.begin(), all.end(), 0);
  expect_three_valued(5, all);
}

TEST(DsssCodes, Gold63FamilyCrossCorrelationIsThreeValued) {
  std::vector<std::size_t> all(gold_family_size(6));
  std::iota(all.begin(), all.end(), 0);
  expect_three_valued(6, all);
}

TEST(DsssCodes, LongerGoldFamiliesCrossCorrelationIsThreeValued) {
  // A sample of each family (whole families would take too long under ASan),
  // always including the preferred pair u (index N) and v (index N + 1).
  expect_three_valued(7, {0, 1, 2, 40, 99, 126, 127, 128});
  expect_three_valued(9, {0, 7, 300, 511, 512});
  expect_three_valued(10, {0, 500, 1023, 1024});
}

TEST(DsssCodes, GoldMembersAreDistinctCodes) {
  std::set<std::vector<Chip>> distinct;
  for (std::size_t i = 0; i < gold_family_size(5); ++i) distinct.insert(gold_code(5, i));
  EXPECT_EQ(distinct.size(), gold_family_size(5));
}

TEST(DsssCodes, NamesParseToCanonicalCodes) {
  EXPECT_EQ(code_by_name("barker11").chips, barker11());
  EXPECT_EQ(code_by_name("mseq31").chips, m_sequence(5));
  EXPECT_EQ(code_by_name("mseq1023").chips, m_sequence(10));
  EXPECT_EQ(code_by_name("mseq255").chips, m_sequence(8));
  EXPECT_EQ(code_by_name("gold127").name, "gold127:0");
  EXPECT_EQ(code_by_name("gold127").chips, gold_code(7, 0));
  EXPECT_EQ(code_by_name("gold63:17").chips, gold_code(6, 17));
  EXPECT_EQ(code_by_name("gold31:32").chips, gold_code(5, 32));
}

TEST(DsssCodes, BadNamesThrowNamingTheCode) {
  for (const std::string bad : {"barker13", "mseq30", "mseq", "gold255", "gold31:33",
                                "gold31:", "gold31:x", "walsh64", "", "mseq2047"}) {
    try {
      code_by_name(bad);
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(DsssCodes, DegreesWithoutAFamilyThrow) {
  EXPECT_THROW(m_sequence(4), std::invalid_argument);
  EXPECT_THROW(m_sequence(11), std::invalid_argument);
  EXPECT_THROW(gold_code(8, 0), std::invalid_argument);
  EXPECT_THROW(gold_code(5, 33), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy::dsss
