// The trace's NPY format: the preamble (magic, version, header length), the
// header (a Python dict literal: descr, fortran_order, shape) and the data,
// read byte by byte as little-endian whatever the host. Only what numpy.save
// writes for a C-order float32/float64 array is accepted.
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "rfsitl/channel/stages/trace.hpp"
#include "trace_text.hpp"

namespace rfsitl::channel::trace {
namespace {

constexpr std::string_view kMagic = "\x93NUMPY";

[[noreturn]] void fail_at(const std::string& name, std::size_t offset, const std::string& what,
                          const std::string& why) {
  throw std::invalid_argument(name + ": byte " + std::to_string(offset) + " (" + what +
                              "): " + why);
}

std::uint64_t little_endian(std::span<const std::uint8_t> bytes, std::size_t offset,
                            std::size_t width) {
  std::uint64_t v = 0;
  for (std::size_t i = width; i-- > 0;) v = (v << 8) | bytes[offset + i];
  return v;
}

/// What the header dict says, each field with the offset of its value.
struct Header {
  std::optional<std::string> descr;
  std::optional<bool> fortran_order;
  std::optional<std::vector<std::uint64_t>> shape;
  std::size_t descr_at = 0;
  std::size_t fortran_at = 0;
  std::size_t shape_at = 0;
};

/// A reader of the header's dict literal; offsets are the file's.
class DictReader {
 public:
  DictReader(std::string_view text, std::size_t base, const std::string& name)
      : text_(text), base_(base), name_(name) {}

  Header read() {
    Header h;
    skip_space();
    expect('{');
    while (skip_space(), peek() != '}') {
      const std::size_t key_at = here();
      const std::string key = string_literal("header");
      skip_space();
      expect(':');
      skip_space();
      const std::size_t value_at = here();
      if (key == "descr") {
        if (h.descr) fail(key_at, "header", "field 'descr' appears twice");
        h.descr = string_literal("header field 'descr'");
        h.descr_at = value_at;
      } else if (key == "fortran_order") {
        if (h.fortran_order) fail(key_at, "header", "field 'fortran_order' appears twice");
        h.fortran_order = boolean();
        h.fortran_at = value_at;
      } else if (key == "shape") {
        if (h.shape) fail(key_at, "header", "field 'shape' appears twice");
        h.shape = tuple();
        h.shape_at = value_at;
      } else {
        fail(key_at, "header", "unknown field " + detail::quote(key));
      }
      skip_space();
      if (peek() == ',') ++pos_;
    }
    ++pos_;  // '}'
    skip_space();
    if (pos_ != text_.size()) fail(here(), "header", "text after the closing '}'");
    return h;
  }

 private:
  std::size_t here() const { return base_ + pos_; }
  char peek() const {
    if (pos_ >= text_.size()) fail(here(), "header", "the header ends inside its dict");
    return text_[pos_];
  }
  void skip_space() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n')) ++pos_;
  }
  void expect(char c) {
    if (peek() != c) {
      fail(here(), "header",
           std::string("expected '") + c + "', found " + detail::quote(text_.substr(pos_, 1)));
    }
    ++pos_;
  }
  [[noreturn]] void fail(std::size_t at, const std::string& what, const std::string& why) const {
    fail_at(name_, at, what, why);
  }

  std::string string_literal(const std::string& what) {
    const char q = peek();
    if (q != '\'' && q != '"') fail(here(), what, "expected a quoted string");
    const std::size_t end = text_.find(q, pos_ + 1);
    if (end == std::string_view::npos) fail(here(), what, "unterminated string");
    std::string s(text_.substr(pos_ + 1, end - pos_ - 1));
    pos_ = end + 1;
    return s;
  }

  bool boolean() {
    for (const auto& [word, value] :
         {std::pair{std::string_view("True"), true}, std::pair{std::string_view("False"), false}}) {
      if (text_.substr(pos_, word.size()) == word) {
        pos_ += word.size();
        return value;
      }
    }
    fail(here(), "header field 'fortran_order'", "expected True or False");
  }

  std::vector<std::uint64_t> tuple() {
    constexpr std::size_t kMaxDims = 32;
    const std::string what = "header field 'shape'";
    if (peek() != '(') fail(here(), what, "expected a tuple '(T, L, 2)'");
    ++pos_;
    std::vector<std::uint64_t> dims;
    while (skip_space(), peek() != ')') {
      std::uint64_t v = 0;
      const char* begin = text_.data() + pos_;
      const auto [ptr, ec] = std::from_chars(begin, text_.data() + text_.size(), v);
      if (ec != std::errc() || ptr == begin) fail(here(), what, "expected a dimension");
      if (dims.size() == kMaxDims) fail(here(), what, "more than 32 dimensions");
      dims.push_back(v);
      pos_ += static_cast<std::size_t>(ptr - begin);
      skip_space();
      if (peek() == ',') {
        ++pos_;
      } else if (peek() != ')') {
        fail(here(), what, "expected ',' or ')'");
      }
    }
    ++pos_;
    return dims;
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t base_;
  const std::string& name_;
};

std::string shape_text(const std::vector<std::uint64_t>& dims) {
  std::string s = "(";
  for (std::size_t i = 0; i < dims.size(); ++i) s += (i ? ", " : "") + std::to_string(dims[i]);
  return s + (dims.size() == 1 ? ",)" : ")");
}

}  // namespace

Trace parse_npy(std::span<const std::uint8_t> bytes, const std::string& name,
                std::span<const LinkIds> links, double step_s) {
  if (bytes.size() > kMaxFileBytes) {
    throw std::invalid_argument(name + ": " + std::to_string(bytes.size()) +
                                " bytes, more than the 256 MiB a trace file may have");
  }
  if (!(step_s > 0.0 && step_s <= kMaxTimeS)) {
    throw std::invalid_argument(name + ": step_s " + detail::number_text(step_s) +
                                " must be in (0, 1e9]");
  }
  // The preamble: magic, version, header length.
  if (bytes.size() < kMagic.size() ||
      std::string_view(reinterpret_cast<const char*>(bytes.data()), kMagic.size()) != kMagic) {
    fail_at(name, 0, "magic", "not an NPY file (it must start with \\x93NUMPY)");
  }
  if (bytes.size() < 8) fail_at(name, bytes.size(), "version", "the file ends in its preamble");
  const unsigned major = bytes[6];
  const unsigned minor = bytes[7];
  if ((major != 1 && major != 2) || minor != 0) {
    fail_at(name, 6, "version",
            "NPY format " + std::to_string(major) + "." + std::to_string(minor) +
                " is not supported (1.0 and 2.0 are)");
  }
  const std::size_t width = major == 1 ? 2 : 4;
  if (bytes.size() < 8 + width) fail_at(name, 8, "header length", "the file ends in its preamble");
  const std::size_t header_at = 8 + width;
  const std::uint64_t header_len = little_endian(bytes, 8, width);
  if (header_len > bytes.size() - header_at) {
    fail_at(name, 8, "header length",
            std::to_string(header_len) + " bytes of header run past the end of the file");
  }
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()) + header_at,
                              static_cast<std::size_t>(header_len));
  const Header h = DictReader(text, header_at, name).read();
  const std::size_t end = header_at + text.size();
  if (!h.descr) fail_at(name, end, "header", "field 'descr' is missing");
  if (!h.fortran_order) fail_at(name, end, "header", "field 'fortran_order' is missing");
  if (!h.shape) fail_at(name, end, "header", "field 'shape' is missing");

  // The array: what numpy.save writes for a C-order float array of (T, L, 2).
  if (*h.descr != "<f4" && *h.descr != "<f8") {
    fail_at(name, h.descr_at, "header field 'descr'",
            detail::quote(*h.descr) + " is not supported (only '<f4' and '<f8')");
  }
  const std::size_t item = *h.descr == "<f4" ? 4 : 8;
  if (*h.fortran_order) {
    fail_at(name, h.fortran_at, "header field 'fortran_order'", "must be False (C order)");
  }
  const std::vector<std::uint64_t>& dims = *h.shape;
  if (dims.size() != 3 || dims[0] == 0 || dims[1] == 0 || dims[1] != links.size() || dims[2] != 2) {
    fail_at(name, h.shape_at, "header field 'shape'",
            shape_text(dims) + " is not (T, L, 2) with T >= 1 and L = " +
                std::to_string(links.size()) + " (the links file's count)");
  }
  const std::uint64_t rows = dims[0];
  if (static_cast<double>(rows - 1) * step_s > kMaxTimeS) {
    fail_at(name, h.shape_at, "header field 'shape'",
            std::to_string(rows) + " rows of step_s " + detail::number_text(step_s) +
                " last beyond 1e9 s");
  }
  // Overflow-free: the data lies within the file, at most kMaxFileBytes.
  const std::size_t data_bytes = bytes.size() - end;
  const std::uint64_t per_row = std::uint64_t{links.size()} * 2 * item;
  if (rows > data_bytes / per_row || rows * per_row != data_bytes) {
    fail_at(name, end, "data",
            "shape " + shape_text(dims) + " of " + *h.descr + " needs " +
                (rows > kMaxFileBytes ? std::string("more") : std::to_string(rows * per_row)) +
                " bytes of data, the file has " + std::to_string(data_bytes));
  }

  auto value_at = [&](std::size_t offset) {
    const std::uint64_t bits = little_endian(bytes, offset, item);
    return item == 4 ? double{std::bit_cast<float>(static_cast<std::uint32_t>(bits))}
                     : std::bit_cast<double>(bits);
  };
  Trace trace;
  trace.links.reserve(links.size());
  for (const LinkIds& l : links) {
    trace.links.push_back({l, {}});
    trace.links.back().samples.reserve(static_cast<std::size_t>(rows));
  }
  std::size_t offset = end;
  for (std::size_t k = 0; k < rows; ++k) {
    for (std::size_t l = 0; l < links.size(); ++l) {
      const Sample s{static_cast<double>(k) * step_s, value_at(offset), value_at(offset + item)};
      // Spelled out only for an error: this loop may run 10^7 times.
      auto where = [&](const char* field) {
        return "row " + std::to_string(k) + ", link " + detail::link_name(links[l]) + ", " + field;
      };
      if (!(s.gain_db >= kMinGainDb && s.gain_db <= kMaxGainDb)) {
        fail_at(name, offset, where("gain_db"),
                detail::number_text(s.gain_db) + " is outside [-300, 100]");
      }
      if (!(std::abs(s.phase_deg) <= kMaxPhaseDeg)) {
        fail_at(name, offset + item, where("phase_deg"),
                detail::number_text(s.phase_deg) + " is outside [-1e9, 1e9]");
      }
      trace.links[l].samples.push_back(s);
      offset += 2 * item;
    }
  }
  return trace;
}

}  // namespace rfsitl::channel::trace
