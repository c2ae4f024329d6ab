#pragma once
/// A campaign run: the planned runs not yet in the table run as child
/// processes, the table and the manifest rewritten (atomically) after each, so
/// an interrupted campaign leaves only complete rows and a re-run resumes.
///
/// The output folder holds:
///   results.csv    the table (results_table.hpp)
///   manifest.json  rfsitl's version, the base scenario and its fingerprint,
///                  the campaign's command, and per row its scenario hash,
///                  wall seconds and the exact command that re-runs it
///   runs/<key>/    each run's summary.json and log.txt
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "rfsitl/campaign/campaign_spec.hpp"

namespace rfsitl::campaign {

/// Where a campaign stands, for a progress line.
struct CampaignProgress {
  std::size_t total = 0;   ///< rows of the table when complete
  std::size_t reused = 0;  ///< already in the table at the start (not run again)
  std::size_t done = 0;    ///< run by this campaign, ok or failed
  std::size_t failed = 0;  ///< of `done`
  std::size_t running = 0;
  double elapsed_s = 0.0;
  double eta_s = -1.0;  ///< wall seconds to go; < 0: not known yet
};

struct CampaignOptions {
  std::string program;  ///< the rfsitl executable each run is a child of
  std::size_t jobs = 1;
  bool retry_failed = false;         ///< run again the rows that failed before
  std::vector<std::string> command;  ///< the campaign's own command line, for the manifest
  /// Polled between steps; may block up to ~50 ms (it is the campaign's wait).
  /// True: stop the children, keep the table's complete rows, return.
  std::function<bool()> interrupted;
  std::function<void(const CampaignProgress&)> progress;  ///< after every change
};

struct CampaignOutcome {
  CampaignProgress progress;
  bool interrupted = false;
  /// Rows of the table found at the start that this campaign's plan does not
  /// hold (a value or the scenario changed since): left out of the new table
  /// (their runs' summaries stay in runs/).
  std::size_t dropped = 0;
  std::string table_path;
  std::string manifest_path;
};

/// Plans (validating every grid point: CampaignError before anything runs),
/// reads the table already there (resume), runs the rest. Throws
/// CampaignError for a bad campaign or a table that is not this campaign's,
/// std::runtime_error when the output cannot be written.
CampaignOutcome run_campaign(const CampaignSpec& spec, const CampaignOptions& options);

}  // namespace rfsitl::campaign
