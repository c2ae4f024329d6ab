/// The campaign's loop: resume from the table, run the rest as children,
/// rewrite the table and the manifest after each run.
#include "rfsitl/campaign/campaign_run.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "rfsitl/campaign/child_pool.hpp"
#include "rfsitl/campaign/results_table.hpp"
#include "rfsitl/campaign/run_figures.hpp"
#include "rfsitl/campaign/run_plan.hpp"
#include "rfsitl/common/build_version.hpp"

namespace fs = std::filesystem;

namespace rfsitl::campaign {
namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Writes beside, then renames: a reader (or an interruption) sees the old
/// file or the new one, never half of one.
void write_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write");
  }
  fs::rename(tmp, path);
}

/// Why a run failed, from its log: the last line `rfsitl run` wrote about an
/// error, else the log's last line.
std::string failure_text(const ChildEnd& end, double timeout_s, const fs::path& log) {
  std::ifstream in(log);
  std::string line;
  std::string last;
  std::string said;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    last = line;
    if (line.rfind("rfsitl run: ", 0) == 0) said = line;
  }
  const std::string why = said.empty() ? last : said;
  return end.describe(timeout_s) + (why.empty() ? "" : ": " + why);
}

ResultRow row_of(const PlannedRun& run) {
  ResultRow row;
  row.values = run.values;
  row.seed = run.seed;
  row.scenario_hash = run.scenario_hash;
  return row;
}

/// The row a finished child leaves: its summary's figures, or why it failed.
ResultRow finished_row(const PlannedRun& run, const ChildEnd& end, double timeout_s,
                       const fs::path& run_dir) {
  ResultRow row = row_of(run);
  row.status = std::string(kStatusFailed);
  if (!end.succeeded()) {
    row.error = failure_text(end, timeout_s, run_dir / "log.txt");
    return row;
  }
  try {
    row.figures = run_figures(nlohmann::json::parse(read_text(run_dir / "summary.json")));
    row.status = std::string(kStatusOk);
  } catch (const std::exception& e) {
    row.error = std::string("summary.json: ") + e.what();
  }
  return row;
}

/// The manifest: how to reproduce the campaign and each of its rows.
struct Manifest {
  nlohmann::json head;
  std::map<std::string, double> wall_s;  ///< by run key, kept across resumes

  std::string text(const std::vector<PlannedRun>& plan,
                   const std::vector<std::optional<ResultRow>>& rows,
                   const std::string& program) const {
    nlohmann::json j = head;
    j["rows"] = nlohmann::json::array();
    for (std::size_t i = 0; i < plan.size(); ++i) {
      if (!rows[i]) continue;
      const PlannedRun& r = plan[i];
      std::vector<std::string> command = {program};
      command.insert(command.end(), r.arguments.begin(), r.arguments.end());
      nlohmann::json row = {{"key", r.key},
                            {"seed", r.seed},
                            {"scenario_hash", r.scenario_hash},
                            {"status", rows[i]->status},
                            {"command", shell_line(command)},
                            {"arguments", command}};
      if (const auto w = wall_s.find(r.key); w != wall_s.end()) row["wall_s"] = w->second;
      j["rows"].push_back(std::move(row));
    }
    return j.dump(2) + "\n";
  }
};

}  // namespace

CampaignOutcome run_campaign(const CampaignSpec& spec, const CampaignOptions& o) {
  const fs::path out = spec.output_dir;
  const fs::path runs_dir = out / "runs";
  const std::vector<PlannedRun> plan = plan_runs(spec, runs_dir.string());
  const std::vector<std::string> keys = spec.parameter_keys();

  std::error_code ec;
  fs::create_directories(runs_dir, ec);
  if (ec) throw std::runtime_error(runs_dir.string() + ": cannot create: " + ec.message());
  CampaignOutcome outcome;
  outcome.table_path = (out / "results.csv").string();
  outcome.manifest_path = (out / "manifest.json").string();

  // Resume: the rows already there, by identity; failed ones run again if asked.
  std::map<std::string, ResultRow> previous;
  if (fs::exists(outcome.table_path)) {
    for (ResultRow& row : parse_csv(read_text(outcome.table_path), outcome.table_path, keys).rows) {
      previous.emplace(row.identity(), std::move(row));
    }
  }
  Manifest manifest;
  if (fs::exists(outcome.manifest_path)) {
    try {
      const nlohmann::json earlier = nlohmann::json::parse(read_text(outcome.manifest_path));
      for (const auto& r : earlier.at("rows")) {
        if (r.contains("wall_s")) manifest.wall_s[r["key"]] = r["wall_s"].get<double>();
      }
    } catch (const std::exception&) {
      // Wall seconds of earlier runs are a courtesy; the table is what counts.
    }
  }
  manifest.head = {{"rfsitl_version", build_version()},
                   {"campaign", fs::absolute(spec.source).string()},
                   {"scenario", fs::absolute(spec.scenario_path).string()},
                   {"scenario_fingerprint", fingerprint(read_text(spec.scenario_path))},
                   {"parameters", keys},
                   {"seeds", spec.seeds},
                   {"command", o.command},
                   {"fingerprint",
                    "FNV-1a 64 of the scenario file's bytes, then for each "
                    "setting in order a NUL and key=value"}};

  std::vector<std::optional<ResultRow>> rows(plan.size());
  std::vector<std::size_t> to_run;
  CampaignProgress progress;
  progress.total = plan.size();
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const auto it = previous.find(row_of(plan[i]).identity());
    if (it == previous.end()) {
      to_run.push_back(i);
      continue;
    }
    if (o.retry_failed && it->second.status == kStatusFailed) {
      to_run.push_back(i);
    } else {
      rows[i] = it->second;
      ++progress.reused;
    }
    previous.erase(it);
  }
  outcome.dropped = previous.size();
  const auto save = [&] {
    ResultsTable table{keys, {}};
    for (const auto& r : rows) {
      if (r) table.rows.push_back(*r);
    }
    write_atomically(outcome.table_path, to_csv(table));
    write_atomically(outcome.manifest_path, manifest.text(plan, rows, o.program));
  };
  save();

  const auto started = std::chrono::steady_clock::now();
  double run_seconds = 0.0;  // summed over finished runs, for the ETA
  const auto report = [&](std::size_t running) {
    progress.running = running;
    progress.elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const std::size_t left = to_run.size() - progress.done;
    progress.eta_s = progress.done == 0 ? -1.0
                                        : run_seconds / double(progress.done) * double(left) /
                                              double(std::min<std::size_t>(o.jobs, left + 1));
    if (o.progress) o.progress(progress);
  };
  ChildPool pool(o.program, o.jobs, spec.timeout_s);
  std::size_t next = 0;
  report(0);
  // The wait between polls: the caller's (it takes signals there) or a nap.
  const auto stop_asked = [&o] {
    if (o.interrupted) return o.interrupted();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return false;
  };
  while (progress.done < to_run.size()) {
    if (stop_asked()) {
      pool.stop_all();
      outcome.interrupted = true;
      break;
    }
    while (next < to_run.size() && pool.has_room()) {
      const PlannedRun& run = plan[to_run[next]];
      const fs::path dir = runs_dir / run.key;
      fs::create_directories(dir);
      fs::remove(dir / "summary.json", ec);  // an earlier attempt's must not pass for this one's
      pool.start(to_run[next], run.arguments, (dir / "log.txt").string());
      ++next;
      report(pool.running());
    }
    for (const auto& [index, end] : pool.reap()) {
      rows[index] = finished_row(plan[index], end, spec.timeout_s, runs_dir / plan[index].key);
      manifest.wall_s[plan[index].key] = end.wall_s;
      run_seconds += end.wall_s;
      ++progress.done;
      if (rows[index]->status == kStatusFailed) ++progress.failed;
      save();
      report(pool.running());
    }
  }
  outcome.progress = progress;
  return outcome;
}

}  // namespace rfsitl::campaign
