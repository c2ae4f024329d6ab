#pragma once
/// Text that came from a client (a hello's program name, a location line, an
/// HTTP target or Host header, ...) made safe to put in a log line. A client
/// must not be able to forge log lines (a line feed followed by a fake
/// "[warn] ..."), move the cursor or recolour the terminal (escape sequences),
/// reorder what a reader sees (bidirectional overrides), or flood the log with
/// one huge string. Every log site that prints client text passes it through
/// log_text() once, at the site, so the rule lives here only.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace rfsitl {

namespace detail {

/// Length of the well-formed UTF-8 sequence at the start of `s` and its code
/// point, or 0 when it is not one (stray continuation byte, overlong form,
/// surrogate, beyond U+10FFFF, cut short).
inline std::size_t utf8_sequence(std::string_view s, char32_t& cp) {
  const auto b = [&](std::size_t i) { return static_cast<std::uint8_t>(s[i]); };
  const std::uint8_t lead = b(0);
  // Lead byte -> length, its payload bits and the smallest code point that
  // needs this length (anything smaller is an overlong, forbidden form).
  std::size_t n = 0;
  char32_t min = 0;
  if (lead >= 0xC2 && lead <= 0xDF) {
    n = 2;
    min = 0x80;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    n = 3;
    min = 0x800;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    n = 4;
    min = 0x10000;
  } else {
    return 0;
  }
  cp = lead & (0x7FU >> n);
  if (s.size() < n) return 0;
  for (std::size_t i = 1; i < n; ++i) {
    if ((b(i) & 0xC0U) != 0x80U) return 0;
    cp = (cp << 6) | (b(i) & 0x3FU);
  }
  if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

/// Code points that are printable but change how the line reads: C1 controls
/// (0x9B is a terminal's one-byte CSI), the line and paragraph separators, and
/// the bidirectional marks, embeddings, overrides and isolates.
constexpr bool invisible_control(char32_t cp) {
  return (cp >= 0x80 && cp <= 0x9F) || cp == 0x2028 || cp == 0x2029 || cp == 0x200E ||
         cp == 0x200F || (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069);
}

inline void append_hex(std::string& out, std::uint32_t v, int digits) {
  constexpr char kHex[] = "0123456789abcdef";
  for (int d = digits - 1; d >= 0; --d) out += kHex[(v >> (4 * d)) & 0xFU];
}

}  // namespace detail

/// Longest part of a client string that log_text() prints by default.
inline constexpr std::size_t kLogTextMaxBytes = 200;

/// `text` as one printable line: printable ASCII and well-formed UTF-8 as they
/// are; a backslash doubled; \n, \r and \t as those two characters; other
/// control bytes and bytes that are not UTF-8 as \xHH; the code points of
/// detail::invisible_control() as \u{HHHH}. Of a text longer than `max_bytes`
/// only its first `max_bytes` bytes (whole characters) are shown, followed by
/// "...(N more bytes)". The result never contains a control character, so it
/// cannot end or rewrite the line it is printed in.
inline std::string log_text(std::string_view text, std::size_t max_bytes = kLogTextMaxBytes) {
  std::string out;
  out.reserve(text.size() < max_bytes ? text.size() : max_bytes);
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<std::uint8_t>(text[i]);
    char32_t cp = 0;
    const std::size_t n = c < 0x80 ? 1 : detail::utf8_sequence(text.substr(i), cp);
    if (i + (n == 0 ? 1 : n) > max_bytes) break;
    if (n == 0) {  // not UTF-8: show the byte
      out += "\\x";
      detail::append_hex(out, c, 2);
      ++i;
      continue;
    }
    if (n > 1) {
      if (detail::invisible_control(cp)) {
        out += "\\u{";
        detail::append_hex(out, cp, 4);
        out += '}';
      } else {
        out.append(text.substr(i, n));
      }
      i += n;
      continue;
    }
    ++i;
    switch (c) {
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7F) {
          out += "\\x";
          detail::append_hex(out, c, 2);
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  if (i < text.size()) out += "...(" + std::to_string(text.size() - i) + " more bytes)";
  return out;
}

}  // namespace rfsitl
