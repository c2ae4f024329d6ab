#include "rfsitl/campaign/metric_plot.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>

#include "rfsitl/campaign/campaign_spec.hpp"
#include "rfsitl/campaign/run_figures.hpp"
#include "rfsitl/campaign/svg_writer.hpp"

namespace rfsitl::campaign {
namespace {

std::optional<double> number_of(const std::string& text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

/// "Nice" tick positions (1, 2 or 5 times a power of ten) covering [lo, hi].
std::vector<double> ticks(double lo, double hi) {
  const double span = hi - lo;
  const double raw = span / 5.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * power;
    if (span / step <= 6.0) break;
  }
  std::vector<double> out;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + step * 1e-9; t += step) {
    out.push_back(std::fabs(t) < step * 1e-9 ? 0.0 : t);
  }
  return out;
}

/// The figure's frame: the data range mapped into the plotting area.
struct Frame {
  double left = 70, right = 190, top = 40, bottom = 60;  ///< margins (legend on the right)
  double width = 760, height = 460;
  double x_lo, x_hi, y_lo, y_hi;

  double px(double x) const { return left + (x - x_lo) / (x_hi - x_lo) * (width - left - right); }
  double py(double y) const {
    return height - bottom - (y - y_lo) / (y_hi - y_lo) * (height - top - bottom);
  }
};

/// [lo, hi] widened a little, and never empty.
void pad(double& lo, double& hi) {
  if (hi - lo < 1e-12 * std::max(1.0, std::fabs(hi))) {
    lo -= std::max(0.5, std::fabs(lo) * 0.1);
    hi += std::max(0.5, std::fabs(hi) * 0.1);
    return;
  }
  const double margin = 0.05 * (hi - lo);
  lo -= margin;
  hi += margin;
}

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

}  // namespace

MetricPlot metric_plot(const ResultsTable& table, const std::string& metric,
                       const std::string& by) {
  const auto by_it = std::find(table.parameter_keys.begin(), table.parameter_keys.end(), by);
  if (by_it == table.parameter_keys.end()) {
    std::string keys;
    for (const auto& k : table.parameter_keys) keys += (keys.empty() ? "" : ", ") + k;
    throw CampaignError("--by " + by + ": not a parameter of this campaign (" +
                        (keys.empty() ? std::string("it has none") : keys) + ")");
  }
  const std::size_t by_index = static_cast<std::size_t>(by_it - table.parameter_keys.begin());
  // The other parameters that take more than one value label the series.
  std::vector<std::size_t> others;
  for (std::size_t k = 0; k < table.parameter_keys.size(); ++k) {
    if (k == by_index) continue;
    for (const ResultRow& r : table.rows) {
      if (r.values[k] != table.rows.front().values[k]) {
        others.push_back(k);
        break;
      }
    }
  }
  MetricPlot plot{metric, by, true, {}};
  std::vector<std::string> x_order;  // by's values in the table's order
  // series label -> x text -> the metric's values over seeds
  std::vector<std::pair<std::string, std::map<std::string, std::vector<double>>>> groups;
  for (const ResultRow& r : table.rows) {
    if (std::find(x_order.begin(), x_order.end(), r.values[by_index]) == x_order.end()) {
      x_order.push_back(r.values[by_index]);
    }
    const auto f = r.figures.find(metric);
    if (r.status != kStatusOk || f == r.figures.end()) continue;
    const std::optional<double> y = number_of(f->second);
    if (!y) continue;
    std::string label;
    for (const std::size_t k : others) {
      label += (label.empty() ? "" : ", ") + table.parameter_keys[k] + "=" + r.values[k];
    }
    auto g =
        std::find_if(groups.begin(), groups.end(), [&](const auto& e) { return e.first == label; });
    if (g == groups.end()) g = groups.insert(groups.end(), {label, {}});
    g->second[r.values[by_index]].push_back(*y);
  }
  if (groups.empty()) {
    throw CampaignError("--plot " + metric +
                        ": no successful row has this figure (see the "
                        "table's header for the figures it has)");
  }
  for (const std::string& x : x_order) plot.numeric_x = plot.numeric_x && number_of(x);
  for (auto& [label, by_x] : groups) {
    PlotSeries s{label, {}};
    for (std::size_t i = 0; i < x_order.size(); ++i) {
      const auto it = by_x.find(x_order[i]);
      if (it == by_x.end()) continue;
      s.points.push_back(
          {x_order[i], plot.numeric_x ? *number_of(x_order[i]) : double(i), mean_ci95(it->second)});
    }
    std::sort(s.points.begin(), s.points.end(),
              [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
    plot.series.push_back(std::move(s));
  }
  return plot;
}

std::string svg_of(const MetricPlot& plot) {
  Frame f;
  f.x_lo = f.y_lo = INFINITY;
  f.x_hi = f.y_hi = -INFINITY;
  std::vector<std::pair<double, std::string>> categories;
  for (const PlotSeries& s : plot.series) {
    for (const PlotPoint& p : s.points) {
      f.x_lo = std::min(f.x_lo, p.x);
      f.x_hi = std::max(f.x_hi, p.x);
      f.y_lo = std::min(f.y_lo, p.y.mean - p.y.half_width);
      f.y_hi = std::max(f.y_hi, p.y.mean + p.y.half_width);
      if (!plot.numeric_x) categories.emplace_back(p.x, p.x_text);
    }
  }
  pad(f.x_lo, f.x_hi);
  pad(f.y_lo, f.y_hi);
  SvgWriter svg(f.width, f.height);
  const double x0 = f.left;
  const double x1 = f.width - f.right;
  const double y0 = f.height - f.bottom;
  const double y1 = f.top;
  svg.rect(0, 0, f.width, f.height, "fill=\"white\"");
  const std::string axis = "stroke=\"#333\" stroke-width=\"1\"";
  const std::string grid = "stroke=\"#ddd\" stroke-width=\"1\"";
  svg.line(x0, y0, x1, y0, axis);
  svg.line(x0, y0, x0, y1, axis);
  for (const double t : ticks(f.y_lo, f.y_hi)) {
    svg.line(x0, f.py(t), x1, f.py(t), grid);
    svg.text(x0 - 6, f.py(t) + 4, figure_text(t), "end");
  }
  if (plot.numeric_x) {
    for (const double t : ticks(f.x_lo, f.x_hi)) {
      svg.line(f.px(t), y0, f.px(t), y0 + 5, axis);
      svg.text(f.px(t), y0 + 18, figure_text(t), "middle");
    }
  } else {
    for (const auto& [x, text] : categories) {
      svg.line(f.px(x), y0, f.px(x), y0 + 5, axis);
      svg.text(f.px(x), y0 + 18, text, "middle");
    }
  }
  svg.text((x0 + x1) / 2, f.height - 18, plot.by, "middle", "font-size=\"13\"");
  svg.text(x0, 24, plot.metric + ": mean over seeds, 95 % confidence interval (Student t)", "start",
           "font-size=\"14\"");
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    const std::string colour = kColours[i % std::size(kColours)];
    std::string points;
    for (const PlotPoint& p : s.points) {
      points += (points.empty() ? "" : " ") + SvgWriter::number(f.px(p.x)) + "," +
                SvgWriter::number(f.py(p.y.mean));
    }
    svg.polyline(points, "stroke=\"" + colour + "\" stroke-width=\"2\"");
    for (const PlotPoint& p : s.points) {
      const std::string bar = "stroke=\"" + colour + "\" stroke-width=\"1.5\"";
      const double xp = f.px(p.x);
      svg.line(xp, f.py(p.y.mean - p.y.half_width), xp, f.py(p.y.mean + p.y.half_width), bar);
      svg.line(xp - 4, f.py(p.y.mean - p.y.half_width), xp + 4, f.py(p.y.mean - p.y.half_width),
               bar);
      svg.line(xp - 4, f.py(p.y.mean + p.y.half_width), xp + 4, f.py(p.y.mean + p.y.half_width),
               bar);
      svg.raw("<circle cx=\"" + SvgWriter::number(xp) + "\" cy=\"" +
              SvgWriter::number(f.py(p.y.mean)) + "\" r=\"3.5\" fill=\"" + colour +
              "\" data-series=\"" + SvgWriter::escaped(s.label) + "\" data-x=\"" +
              SvgWriter::escaped(p.x_text) + "\" data-mean=\"" + figure_text(p.y.mean) +
              "\" data-ci=\"" + figure_text(p.y.half_width) + "\" data-n=\"" +
              std::to_string(p.y.n) + "\"/>");
    }
    const double ly = y1 + 14 + 18 * static_cast<double>(i);
    svg.line(x1 + 12, ly - 4, x1 + 32, ly - 4, "stroke=\"" + colour + "\" stroke-width=\"2\"");
    svg.text(x1 + 38, ly, s.label.empty() ? plot.metric : s.label, "start");
  }
  return svg.finish();
}

}  // namespace rfsitl::campaign
