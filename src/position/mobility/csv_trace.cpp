#include "rfsitl/position/mobility/csv_trace.hpp"

#include <array>
#include <cctype>
#include <map>
#include <optional>
#include <vector>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"
#include "trace_text.hpp"

namespace rfsitl::position::mobility {
namespace {

constexpr std::size_t kFields = 5;
using Fields = std::array<std::string_view, kFields>;
constexpr Fields kLocalHeader = {"t", "node", "x", "y", "z"};
constexpr Fields kGeodeticHeader = {"t", "node", "lat", "lon", "alt"};

/// Splits at commas into `out` (trimmed); returns how many fields there were,
/// counting those beyond kFields too.
std::size_t split(std::string_view line, Fields& out) {
  std::size_t count = 0;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
    if (count < kFields) out[count] = detail::trim(line.substr(start, end - start));
    ++count;
    if (comma == std::string_view::npos) return count;
    start = comma + 1;
  }
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  }
  return true;
}

bool matches(const Fields& fields, const Fields& header) {
  for (std::size_t i = 0; i < kFields; ++i) {
    if (!equals_ignoring_case(fields[i], header[i])) return false;
  }
  return true;
}

class CsvReader {
 public:
  CsvReader(TraceParseResult& result, const CsvTraceOptions& options)
      : result_(result), origin_(options.origin), form_(options.headerless) {}

  void line(std::size_t number, std::string_view text) {
    if (stopped_ || detail::is_blank_or_comment(text)) return;
    Fields f;
    const std::size_t count = split(text, f);
    const bool first = !seen_content_;
    seen_content_ = true;
    // A header is told by its first field alone, so a data row with a typo in
    // its time is reported as that row, not as a header that ends the file.
    if (first && equals_ignoring_case(f[0], "t")) return header(number, f, count);
    row(number, f, count);
  }

  void finish() {
    for (auto& [node, knots] : knots_) result_.tracks.emplace(node, PiecewiseLinearTrack(knots));
  }

 private:
  void header(std::size_t number, const Fields& f, std::size_t count) {
    if (count == kFields && matches(f, kLocalHeader)) {
      form_ = CsvCoordinates::kLocal;
    } else if (count == kFields && matches(f, kGeodeticHeader)) {
      form_ = CsvCoordinates::kGeodetic;
    } else {
      detail::skip_line(result_, number,
                        "unknown header: expected t,node,x,y,z or t,node,lat,lon,alt; the rest "
                        "of the file is not read");
      stopped_ = true;
    }
  }

  void row(std::size_t number, const Fields& f, std::size_t count) {
    const bool local = form_ == CsvCoordinates::kLocal;
    const Fields& names = local ? kLocalHeader : kGeodeticHeader;
    if (count != kFields) {
      return detail::skip_line(result_, number,
                               "expected 5 comma-separated fields (t, node, " +
                                   std::string(names[2]) + ", " + std::string(names[3]) + ", " +
                                   std::string(names[4]) + "), got " + std::to_string(count));
    }
    std::array<double, kFields> v{};
    for (std::size_t i : {0, 2, 3, 4}) {
      const auto n = detail::parse_number(f[i]);
      if (!n) {
        return detail::skip_line(
            result_, number,
            std::string(names[i]) + " " + detail::quote(f[i]) + " is not a finite number");
      }
      v[i] = *n;
    }
    if (std::string why = detail::time_error(v[0]); !why.empty()) {
      return detail::skip_line(result_, number, std::move(why));
    }
    const auto node = detail::parse_node(f[1]);
    if (!node) {
      return detail::skip_line(result_, number,
                               "node " + detail::quote(f[1]) + " is not an integer in 0..65535");
    }
    const Position p = local ? Position{LocalPosition{v[2], v[3], v[4]}}
                             : Position{GeodeticPosition{v[2], v[3], v[4]}};
    if (std::string why = detail::sample_position_error(p); !why.empty()) {
      return detail::skip_line(result_, number, std::move(why));
    }
    std::vector<TrackKnot>& knots = knots_[*node];
    if (!knots.empty() && v[0] < knots.back().time_s) {
      return detail::skip_line(result_, number,
                               "t " + format_coordinate(v[0]) + " is before node " +
                                   std::to_string(*node) + "'s previous sample at t " +
                                   format_coordinate(knots.back().time_s));
    }
    knots.push_back({v[0], to_local(p, origin_)});
  }

  TraceParseResult& result_;
  GeodeticPosition origin_;
  CsvCoordinates form_;
  bool seen_content_ = false;
  bool stopped_ = false;
  std::map<std::uint32_t, std::vector<TrackKnot>> knots_;
};

}  // namespace

TraceParseResult parse_csv_trace(std::string_view text, std::string source,
                                 const CsvTraceOptions& options) {
  TraceParseResult result;
  result.source = std::move(source);
  CsvReader reader(result, options);
  detail::for_each_line(text, [&](std::size_t n, std::string_view line) { reader.line(n, line); });
  reader.finish();
  return result;
}

TraceParseResult read_csv_trace(const std::string& path, const CsvTraceOptions& options) {
  return parse_csv_trace(detail::read_text_file(path), path, options);
}

}  // namespace rfsitl::position::mobility
