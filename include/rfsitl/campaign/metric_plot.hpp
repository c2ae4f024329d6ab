#pragma once
/// A metric of the results table against one parameter: its mean over seeds
/// with a 95 % confidence interval at each value, one series per combination
/// of the other parameters that vary; and that plot as SVG.
#include <string>
#include <vector>

#include "rfsitl/campaign/results_table.hpp"
#include "rfsitl/campaign/statistics.hpp"

namespace rfsitl::campaign {

struct PlotPoint {
  std::string x_text;  ///< the parameter's value as written
  double x = 0.0;      ///< its number; on a categorical axis its position 0, 1, ...
  MeanInterval y;
};

struct PlotSeries {
  std::string label;              ///< "mac.type=csma, phy.type=ofdm"; "" when nothing else varies
  std::vector<PlotPoint> points;  ///< by x
};

struct MetricPlot {
  std::string metric;
  std::string by;
  bool numeric_x = true;           ///< every value of `by` is a number
  std::vector<PlotSeries> series;  ///< in the order the table first shows them
};

/// From the rows with status ok that have the metric. Throws CampaignError
/// when `by` is not a parameter column or no row has `metric`.
MetricPlot metric_plot(const ResultsTable& table, const std::string& metric, const std::string& by);

/// The plot as an SVG document: axes with ticks, a line per series through its
/// means, the intervals as error bars, a legend. Each mean is a <circle> with
/// data-x, data-mean, data-ci and data-n attributes (the exact figures).
std::string svg_of(const MetricPlot& plot);

}  // namespace rfsitl::campaign
