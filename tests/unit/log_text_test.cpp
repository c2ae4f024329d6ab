// log_text(): client text can neither end nor rewrite the log line it is
// printed in, and stays readable.
#include "rfsitl/common/log_text.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace rfsitl {
namespace {

/// True when `s` holds no C0 control, DEL or C1 control byte sequence a
/// terminal would act on.
bool printable_line(const std::string& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7F) return false;
    if (c == 0xC2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) <= 0x9F) return false;
  }
  return true;
}

TEST(LogText, ALineFeedCannotForgeALogLine) {
  const std::string forged = "gnuradio\n[2030-01-01 00:00:00.000] [error] node 1: forged";
  const std::string shown = log_text(forged);
  EXPECT_EQ(shown, "gnuradio\\n[2030-01-01 00:00:00.000] [error] node 1: forged");
  EXPECT_EQ(log_text("a\rb\tc"), "a\\rb\\tc");
  // A backslash is doubled, so "\n" typed by the client reads differently
  // from an escaped line feed.
  EXPECT_EQ(log_text("a\\nb"), "a\\\\nb");
}

TEST(LogText, TerminalControlsAreShownNotActedOn) {
  EXPECT_EQ(log_text("\x1b[2J\x1b[31mred"), "\\x1b[2J\\x1b[31mred");
  EXPECT_EQ(log_text(std::string("nul\0del\x7f", 8)), "nul\\x00del\\x7f");
  EXPECT_EQ(log_text("\xc2\x9b"
                     "31m"),
            "\\u{009b}31m");  // C1 CSI, as UTF-8
  EXPECT_EQ(log_text("x\xe2\x80\xae"
                     "cod.exe"),
            "x\\u{202e}cod.exe");                        // right-to-left override
  EXPECT_EQ(log_text("a\xe2\x80\xa8z"), "a\\u{2028}z");  // line separator
}

TEST(LogText, ReadableUtf8StaysAndBrokenBytesAreShownInHex) {
  EXPECT_EQ(log_text("Émetteur ✈ 無人機"), "Émetteur ✈ 無人機");
  EXPECT_EQ(log_text("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(log_text("\xc0\xaf"), "\\xc0\\xaf");           // overlong '/'
  EXPECT_EQ(log_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a UTF-16 surrogate
  EXPECT_EQ(log_text("ab\xe2\x9c"), "ab\\xe2\\x9c");       // cut inside a character
}

TEST(LogText, LongTextIsCutAtWholeCharactersAndSaysHowMuchIsLeft) {
  EXPECT_EQ(log_text(std::string(300, 'a')), std::string(200, 'a') + "...(100 more bytes)");
  EXPECT_EQ(log_text("abcd", 4), "abcd");
  EXPECT_EQ(log_text("ab✈", 4), "ab...(3 more bytes)");  // never half a character
}

TEST(LogText, AnyBytesGiveOnePrintableLine) {
  std::mt19937 rng(15);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<std::size_t> length(0, 64);
  for (int n = 0; n < 20000; ++n) {
    std::string s(length(rng), '\0');
    for (char& c : s) c = static_cast<char>(byte(rng));
    const std::string shown = log_text(s);
    ASSERT_TRUE(printable_line(shown)) << shown;
  }
}

}  // namespace
}  // namespace rfsitl
