// The pattern file (antenna.hpp's comment gives the format): parsing, with
// every fault named by file and line, and the bilinear look-up.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "rfsitl/channel/stages/antenna.hpp"

namespace rfsitl::channel::antenna {
namespace {

constexpr double kMinGainDbi = -200.0;
constexpr double kMaxGainDbi = 100.0;
// A last column at 360 repeats column 0: the same decimal text parses to the
// same double, so any difference above this is a real inconsistency.
constexpr double kWrapToleranceDb = 1e-9;

/// The shortest decimal text of `v`, for messages.
std::string number_text(double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

std::string_view trim(std::string_view s) {
  const auto is_blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

/// Reads a text line by line, numbering from 1, skipping blank and '#' lines.
class ContentLines {
 public:
  explicit ContentLines(std::string_view text) : text_(text) {}

  /// The next content line (trimmed), or nullopt at the end.
  std::optional<std::string_view> next() {
    while (start_ < text_.size()) {
      std::size_t end = text_.find('\n', start_);
      if (end == std::string_view::npos) end = text_.size();
      const std::string_view line = trim(text_.substr(start_, end - start_));
      start_ = end + 1;
      ++number_;
      if (!line.empty() && line.front() != '#') return line;
    }
    return std::nullopt;
  }

  /// The number of the line last returned (or of the last line, at the end).
  std::size_t number() const { return std::max<std::size_t>(number_, 1); }

 private:
  std::string_view text_;
  std::size_t start_ = 0;
  std::size_t number_ = 0;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& name) : lines_(text), name_(name) {}

  PatternGrid run() {
    const auto header = lines_.next();
    if (!header) fail("no header row (a label, then the azimuths)");
    read_azimuths(*header);
    while (const auto line = lines_.next()) read_row(*line);
    if (elevations_.size() < 2) {
      fail("at least 2 elevation rows are needed, found " + std::to_string(elevations_.size()));
    }
    if (elevations_.back() != 90.0) {
      fail("the elevations must end at 90, not " + number_text(elevations_.back()));
    }
    if (azimuths_.back() < 360.0) close_the_circle();
    return PatternGrid(std::move(azimuths_), std::move(elevations_), std::move(gains_));
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    throw std::invalid_argument(name_ + ":" + std::to_string(lines_.number()) + ": " + reason);
  }

  /// The comma-separated cells of `line`, each trimmed.
  static std::vector<std::string_view> cells_of(std::string_view line) {
    std::vector<std::string_view> cells;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      cells.push_back(trim(line.substr(
          start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) return cells;
      start = comma + 1;
    }
  }

  /// Cell `column` (1-based) as a finite number.
  double number(std::string_view cell, std::size_t column) const {
    const std::string where = "cell " + std::to_string(column);
    if (cell.empty()) fail(where + " is empty");
    double v = 0.0;
    const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
    if (error != std::errc() || end != cell.data() + cell.size() || !std::isfinite(v)) {
      fail(where + " is not a finite decimal number");
    }
    return v;
  }

  void read_azimuths(std::string_view line) {
    const std::vector<std::string_view> cells = cells_of(line);
    if (cells.size() < 3) fail("the header row needs a label cell and at least 2 azimuths");
    for (std::size_t c = 1; c < cells.size(); ++c) {
      const double az = number(cells[c], c + 1);
      if (c == 1 && az != 0.0) fail("the azimuths must start at 0, not " + number_text(az));
      if (c > 1 && !(az > azimuths_.back())) {
        fail("azimuth " + number_text(az) + " (cell " + std::to_string(c + 1) +
             ") is not above the one before it");
      }
      if (az > 360.0) fail("azimuth " + number_text(az) + " is beyond 360");
      azimuths_.push_back(az);
    }
  }

  void read_row(std::string_view line) {
    const std::vector<std::string_view> cells = cells_of(line);
    if (cells.size() != azimuths_.size() + 1) {
      fail("the row has " + std::to_string(cells.size()) + " cells, the header " +
           std::to_string(azimuths_.size() + 1));
    }
    const double el = number(cells[0], 1);
    if (elevations_.empty() && el != -90.0) {
      fail("the elevations must start at -90, not " + number_text(el));
    }
    if (!elevations_.empty() && !(el > elevations_.back())) {
      fail("elevation " + number_text(el) + " is not above the one before it");
    }
    if (el > 90.0) fail("elevation " + number_text(el) + " is beyond 90");
    elevations_.push_back(el);
    const std::size_t row_start = gains_.size();
    for (std::size_t c = 1; c < cells.size(); ++c) {
      const double g = number(cells[c], c + 1);
      if (g < kMinGainDbi || g > kMaxGainDbi) {
        fail("gain " + number_text(g) + " (cell " + std::to_string(c + 1) + ") is outside [" +
             number_text(kMinGainDbi) + ", " + number_text(kMaxGainDbi) + "] dBi");
      }
      gains_.push_back(g);
    }
    if (azimuths_.back() == 360.0 &&
        std::abs(gains_.back() - gains_[row_start]) > kWrapToleranceDb) {
      fail("the gain at azimuth 360 (" + number_text(gains_.back()) +
           ") differs from the one at 0 (" + number_text(gains_[row_start]) + ")");
    }
  }

  /// Appends the 360 column (column 0 again), so the look-up needs no wrap.
  void close_the_circle() {
    const std::size_t columns = azimuths_.size();
    std::vector<double> closed;
    closed.reserve(elevations_.size() * (columns + 1));
    for (std::size_t r = 0; r < elevations_.size(); ++r) {
      const auto row = gains_.begin() + static_cast<std::ptrdiff_t>(r * columns);
      closed.insert(closed.end(), row, row + static_cast<std::ptrdiff_t>(columns));
      closed.push_back(*row);
    }
    gains_ = std::move(closed);
    azimuths_.push_back(360.0);
  }

  ContentLines lines_;
  const std::string& name_;
  std::vector<double> azimuths_;
  std::vector<double> elevations_;
  std::vector<double> gains_;
};

/// The segment [axis[i], axis[i + 1]] holding `v` and v's place in it, [0, 1].
/// Precondition: axis strictly increasing, size >= 2, v within its ends.
std::pair<std::size_t, double> locate(const std::vector<double>& axis, double v) {
  const auto above = std::upper_bound(axis.begin(), axis.end(), v);
  const auto i =
      std::clamp<std::size_t>(static_cast<std::size_t>(above - axis.begin()), 1, axis.size() - 1) -
      1;
  return {i, std::clamp((v - axis[i]) / (axis[i + 1] - axis[i]), 0.0, 1.0)};
}

}  // namespace

PatternGrid::PatternGrid(std::vector<double> azimuths_deg, std::vector<double> elevations_deg,
                         std::vector<double> gains_dbi)
    : azimuths_(std::move(azimuths_deg)),
      elevations_(std::move(elevations_deg)),
      gains_(std::move(gains_dbi)) {}

double PatternGrid::gain_dbi(double azimuth_deg, double elevation_deg) const {
  const auto [c, s] = locate(azimuths_, std::clamp(azimuth_deg, 0.0, 360.0));
  const auto [r, t] = locate(elevations_, std::clamp(elevation_deg, -90.0, 90.0));
  const double below = (1.0 - s) * at(r, c) + s * at(r, c + 1);
  const double above = (1.0 - s) * at(r + 1, c) + s * at(r + 1, c + 1);
  return (1.0 - t) * below + t * above;
}

PatternGrid parse_pattern(std::string_view text, const std::string& name) {
  if (text.size() > kMaxPatternBytes) {
    // Named by the line on which the limit is crossed.
    const auto newlines = std::count(text.begin(), text.begin() + kMaxPatternBytes, '\n');
    throw std::invalid_argument(name + ":" + std::to_string(newlines + 1) +
                                ": the file is over the limit of " +
                                std::to_string(kMaxPatternBytes) + " bytes");
  }
  return Parser(text, name).run();
}

PatternGrid load_pattern(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot be opened");
  // One byte past the limit is enough for parse_pattern to refuse the file.
  std::string text(kMaxPatternBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw std::invalid_argument(path + ": cannot be read");
  text.resize(static_cast<std::size_t>(in.gcount()));
  return parse_pattern(text, path);
}

}  // namespace rfsitl::channel::antenna
