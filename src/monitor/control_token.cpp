#include "rfsitl/monitor/control_token.hpp"

#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <array>
#include <boost/asio/ip/address.hpp>
#include <cctype>
#include <fstream>
#include <stdexcept>

namespace rfsitl::monitor {
namespace {

bool token_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '~' ||
         c == '-';
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// Percent-decodes a query value ('+' is a space, as forms send it); nullopt
/// when an escape is malformed.
std::optional<std::string> percent_decode(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out.push_back(' ');
    } else if (s[i] != '%') {
      out.push_back(s[i]);
    } else {
      const int hi = i + 1 < s.size() ? hex_value(s[i + 1]) : -1;
      const int lo = i + 2 < s.size() ? hex_value(s[i + 2]) : -1;
      if (hi < 0 || lo < 0) return std::nullopt;
      out.push_back(static_cast<char>(hi * 16 + lo));
      i += 2;
    }
  }
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

bool bind_is_loopback(std::string_view bind_address) {
  if (iequals(bind_address, "localhost")) return true;
  boost::system::error_code ec;
  const auto a = boost::asio::ip::make_address(std::string(bind_address), ec);
  if (ec) return false;
  if (a.is_v4()) return a.to_v4().is_loopback();
  const auto v6 = a.to_v6();
  if (v6.is_v4_mapped()) {
    return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, v6).is_loopback();
  }
  return v6.is_loopback();
}

std::string control_token_problem(std::string_view token) {
  if (token.size() < kMinControlTokenChars || token.size() > kMaxControlTokenChars) {
    return "must be " + std::to_string(kMinControlTokenChars) + " to " +
           std::to_string(kMaxControlTokenChars) + " characters long, got " +
           std::to_string(token.size());
  }
  for (const char c : token) {
    if (!token_char(c)) {
      return "may contain only letters, digits and . _ ~ - (they need no escaping in a URL)";
    }
  }
  return "";
}

std::string generate_control_token() {
  std::ifstream urandom("/dev/urandom", std::ios::binary);
  std::array<unsigned char, 16> bits{};
  if (!urandom.read(reinterpret_cast<char*>(bits.data()), bits.size())) {
    throw std::runtime_error("cannot read /dev/urandom to draw the dashboard's control token");
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string token;
  for (const unsigned char b : bits) {
    token.push_back(kHex[b >> 4]);
    token.push_back(kHex[b & 0xF]);
  }
  return token;
}

bool control_token_matches(std::string_view given, std::string_view expected) {
  // Every character of `expected` is compared whatever happened before; the
  // length difference joins the same accumulator instead of returning early.
  std::size_t diff = given.size() ^ expected.size();
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const unsigned char g = i < given.size() ? static_cast<unsigned char>(given[i]) : 0;
    diff |= static_cast<unsigned char>(g ^ static_cast<unsigned char>(expected[i]));
  }
  return diff == 0;
}

std::optional<std::string> request_control_token(std::string_view target,
                                                 std::optional<std::string_view> authorization) {
  if (authorization) {
    const std::string_view value = trim(*authorization);
    static constexpr std::string_view kScheme = "bearer";
    if (value.size() > kScheme.size() && iequals(value.substr(0, kScheme.size()), kScheme) &&
        (value[kScheme.size()] == ' ' || value[kScheme.size()] == '\t')) {
      return std::string(trim(value.substr(kScheme.size())));
    }
  }
  const auto q = target.find('?');
  if (q == std::string_view::npos) return std::nullopt;
  std::string_view query = target.substr(q + 1);
  if (const auto hash = query.find('#'); hash != std::string_view::npos)
    query.remove_suffix(query.size() - hash);
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    const auto eq = pair.find('=');
    if (eq == std::string_view::npos || pair.substr(0, eq) != "token") continue;
    return percent_decode(pair.substr(eq + 1));
  }
  return std::nullopt;
}

std::string control_token_refusal(std::string_view target,
                                  std::optional<std::string_view> authorization,
                                  std::string_view expected) {
  if (expected.empty()) return "";
  const auto given = request_control_token(target, authorization);
  if (!given || given->empty()) {
    return "moving nodes needs the dashboard's control token: open the dashboard URL with "
           "?token=... that the emulator printed, or send \"Authorization: Bearer TOKEN\"";
  }
  if (!control_token_matches(*given, expected)) {
    return "wrong control token: moving nodes refused (use the dashboard URL with ?token=... "
           "that the emulator printed)";
  }
  return "";
}

}  // namespace rfsitl::monitor
