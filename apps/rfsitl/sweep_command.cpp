/// `rfsitl sweep`: a campaign of runs (rfsitl/campaign/): the flags, the
/// signals, the progress line; and --plot, a figure of the table it wrote.
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "rfsitl/campaign/campaign_run.hpp"
#include "rfsitl/campaign/metric_plot.hpp"
#include "rfsitl/campaign/results_table.hpp"
#include "rfsitl/campaign/run_plan.hpp"
#include "stop_signals.hpp"

namespace rfsitl::app {
namespace {

struct SweepOptions {
  std::string campaign_path;
  std::size_t jobs = 0;  ///< 0: one per core
  bool retry_failed = false;
  bool dry_run = false;
  std::string output;  ///< overrides the campaign's output:
  std::string plot_metric;
  std::string plot_by;
  std::string plot_out;
  std::vector<std::string> command;  ///< argv, for the manifest
};

/// This program's own path: every run is a child of the same binary.
std::string own_program() {
  std::vector<char> buf(PATH_MAX + 1, '\0');
  const ssize_t n = ::readlink("/proc/self/exe", buf.data(), PATH_MAX);
  if (n <= 0) throw std::runtime_error(std::string("/proc/self/exe: ") + std::strerror(errno));
  return std::string(buf.data(), static_cast<std::size_t>(n));
}

std::string duration_text(double s) {
  if (s < 0) return "?";
  const long t = std::lround(s);
  char buf[32];
  if (t >= 3600) {
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", t / 3600, t / 60 % 60);
  } else if (t >= 60) {
    std::snprintf(buf, sizeof buf, "%ldm%02lds", t / 60, t % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%lds", t);
  }
  return buf;
}

/// One line: rewritten in place on a terminal, a line per finished run otherwise.
class ProgressLine {
 public:
  ProgressLine() : tty_(::isatty(STDOUT_FILENO) == 1) {}

  void show(const campaign::CampaignProgress& p) {
    const std::size_t finished = p.reused + p.done;
    char line[160];
    std::snprintf(line, sizeof line,
                  "rfsitl sweep: %zu/%zu rows (%zu run, %zu failed, %zu reused), %zu running, "
                  "%s elapsed, ETA %s",
                  finished, p.total, p.done, p.failed, p.reused, p.running,
                  duration_text(p.elapsed_s).c_str(), duration_text(p.eta_s).c_str());
    if (tty_) {
      std::printf("\r\033[K%s", line);
    } else if (p.done != last_done_ || first_) {
      std::printf("%s\n", line);
    }
    std::fflush(stdout);
    last_done_ = p.done;
    first_ = false;
  }
  void end() {
    if (tty_ && !first_) std::printf("\n");
  }

 private:
  bool tty_;
  bool first_ = true;
  std::size_t last_done_ = 0;
};

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw campaign::CampaignError(path + ": cannot read: " + std::strerror(errno));
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// --plot: the figure of a table the campaign wrote.
int plot(const campaign::CampaignSpec& spec, const SweepOptions& o) {
  const std::string table_path = spec.output_dir + "/results.csv";
  const campaign::ResultsTable table =
      campaign::parse_csv(read_text(table_path), table_path, spec.parameter_keys());
  const campaign::MetricPlot figure = campaign::metric_plot(table, o.plot_metric, o.plot_by);
  std::string out = o.plot_out;
  if (out.empty()) out = spec.output_dir + "/" + o.plot_metric + "_by_" + o.plot_by + ".svg";
  std::ofstream file(out, std::ios::binary | std::ios::trunc);
  file << campaign::svg_of(figure);
  file.flush();
  if (!file) throw std::runtime_error(out + ": cannot write");
  std::printf("rfsitl sweep: %s: %s by %s, %zu series\n", out.c_str(), o.plot_metric.c_str(),
              o.plot_by.c_str(), figure.series.size());
  return 0;
}

int sweep(const SweepOptions& o) {
  campaign::CampaignSpec spec;
  try {
    spec = campaign::load_campaign_file(o.campaign_path);
    if (!o.output.empty()) spec.output_dir = o.output;
    if (!o.plot_metric.empty()) return plot(spec, o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl sweep: %s\n", e.what());
    return 2;
  }
  if (o.dry_run) {
    try {
      const auto runs = campaign::plan_runs(spec, spec.output_dir + "/runs");
      std::printf("rfsitl sweep: %s: %zu runs (%zu grid points x %zu seeds), all valid\n",
                  o.campaign_path.c_str(), runs.size(), runs.size() / spec.seeds.size(),
                  spec.seeds.size());
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rfsitl sweep: %s\n", e.what());
      return 2;
    }
  }
  // Signals are taken here, between polls; the runs have process groups of
  // their own, so a Ctrl-C reaches only this process, which stops them.
  const sigset_t signals = block_stop_signals();
  int received = 0;
  campaign::CampaignOptions options;
  options.jobs = o.jobs > 0 ? o.jobs : std::max(1U, std::thread::hardware_concurrency());
  options.retry_failed = o.retry_failed;
  options.command = o.command;
  ProgressLine progress;
  options.progress = [&progress](const campaign::CampaignProgress& p) { progress.show(p); };
  options.interrupted = [&] {
    const timespec poll{0, 20'000'000};
    const int sig = sigtimedwait(&signals, nullptr, &poll);
    if (sig == SIGINT || sig == SIGTERM) received = sig;
    return received != 0;
  };
  campaign::CampaignOutcome outcome;
  try {
    options.program = own_program();
    outcome = campaign::run_campaign(spec, options);
  } catch (const std::exception& e) {
    progress.end();
    std::fprintf(stderr, "rfsitl sweep: %s\n", e.what());
    return 2;
  }
  progress.end();
  if (outcome.dropped > 0) {
    std::printf(
        "rfsitl sweep: %zu row(s) of the earlier table are not in this campaign's grid "
        "(a value or the scenario changed) and were left out; their summaries stay in "
        "runs/\n",
        outcome.dropped);
  }
  const campaign::CampaignProgress& p = outcome.progress;
  if (outcome.interrupted) {
    std::printf(
        "rfsitl sweep: %s: stopped; %zu of %zu rows in %s (run the same command to "
        "resume)\n",
        received == SIGINT ? "SIGINT" : "SIGTERM", p.reused + p.done, p.total,
        outcome.table_path.c_str());
    return 1;
  }
  std::printf("rfsitl sweep: %zu rows in %s (%zu run now, %zu failed, %zu reused); manifest %s\n",
              p.total, outcome.table_path.c_str(), p.done, p.failed, p.reused,
              outcome.manifest_path.c_str());
  return p.failed > 0 ? 1 : 0;
}

}  // namespace

std::function<int()> add_sweep_command(CLI::App& parent, int argc, char** argv) {
  auto opts = std::make_shared<SweepOptions>();
  opts->command.assign(argv, argv + argc);
  CLI::App* cmd = parent.add_subcommand(
      "sweep",
      "Run a campaign: a grid of scenario settings x seeds in virtual time, in parallel, into "
      "one table (results.csv) and a manifest; resumable");
  cmd->add_option("campaign", opts->campaign_path,
                  "Campaign file (YAML; README's 'Campaigns', examples/campaigns/)")
      ->type_name("PATH")
      ->required();
  cmd->add_option("-j,--jobs", opts->jobs, "Runs at once (default: one per core)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--retry-failed", opts->retry_failed,
                "Run again the rows that failed before (by default a row in the table is kept)");
  cmd->add_flag("--dry-run", opts->dry_run,
                "Check the whole campaign (every grid point's scenario) and count its runs; run "
                "nothing");
  cmd->add_option("--output", opts->output, "Output folder instead of the campaign's output:")
      ->type_name("DIR");
  CLI::Option* metric = cmd->add_option(
      "--plot", opts->plot_metric,
      "Plot this figure of the table (a column, e.g. delivery_ratio) instead of running: its mean "
      "over seeds with 95 % confidence intervals, as SVG");
  metric->type_name("METRIC");
  CLI::Option* by = cmd->add_option("--by", opts->plot_by, "The parameter on the plot's x axis")
                        ->type_name("PARAM")
                        ->needs(metric);
  metric->needs(by);
  cmd->add_option("--out", opts->plot_out,
                  "The plot's file (default: <output>/<metric>_by_<param>.svg)")
      ->type_name("FILE.svg")
      ->needs(metric);
  return [opts] { return sweep(*opts); };
}

}  // namespace rfsitl::app
