#pragma once
// A campaign of runs jam did not plan: open runs (docs/cross-simulator.md) of another simulator,
// or jam's own run files gathered by hand, imported into a directory with
// `jam campaign import DIR FILE...`. The directory has the layout of a planned campaign where
// `stats`, `check` and `report` look (runs/<name>.h5, named by ensemble and sample), and
// `external.toml` instead of `campaign.toml`: the model every run shares, the output grid the
// statistics average on, each run's provenance, and the files set aside with the reason.
//
// A run joins only when it is a valid open run of the campaign's model (dim, diameter ratio,
// contact law, dynamics and Q equal to the first run's) and its (N, phi_init, rate, sample) is
// new; any other file is set aside with its reason, never silently averaged, and never copied.
// Importing the same file again is a no-op. The source files are never changed. A file in
// runs/ that external.toml does not list is never replaced, and imports take turns under the
// campaign's lock (campaign/external_import.cpp says how an interrupted one resumes).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/io/open_run.hpp"

namespace jam {

/// An imported run: where it came from and where it is.
struct ExternalRun {
  std::string name;  // runs/<name>.h5, as a planned run's name (run_plan.hpp, run_name)
  std::int64_t n = 0, sample = 0;
  double phi_init = 0, log10_rate = 0;
  std::string source, source_checksum, simulator, simulator_version;
  std::string origin;  // what the run itself names as made from (its `source`: a LAMMPS log...)
};

struct SetAside {
  std::string file, reason;
};

struct ExternalCampaign {
  std::string name;
  double phi_step = 0.0005;  // the grid of packings the statistics average on
  // The model, from the first run imported.
  int dim = 0;
  double diameter_ratio = 0;
  std::string contact, dynamics;
  double quality_factor = 0;  // Q; the record's key "q"
  std::vector<ExternalRun> runs;
  std::vector<SetAside> set_aside;
};

/// One word of letters, digits and . _ + - that begins with a letter, digit or _, at most 255
/// bytes: a campaign's name names the report's directory, so it is never a path.
bool is_plain_campaign_name(const std::string& name);

/// True when `directory` holds external.toml.
bool is_external_campaign(const std::string& directory);

/// Reads DIR/external.toml; throws naming the file and the field.
ExternalCampaign read_external_campaign(const std::string& directory);

/// Writes DIR/external.toml (never through a link: import_store.hpp), and not at all when it
/// already holds this text: its time says when its content last changed (jam pipeline judges
/// what is stale by such times).
void write_external_campaign(const std::string& directory, const ExternalCampaign& c);

/// The entries of DIR/runs that external.toml does not list (a file of someone's, or one an
/// import killed before it listed it), jam's own temporaries aside, as paths: never averaged,
/// never replaced, named by `status` and `stats`.
std::vector<std::string> unlisted_run_files(const std::string& directory,
                                            const ExternalCampaign& c);

struct ImportOptions {
  std::string name;                // default: the directory's name (new campaigns)
  std::optional<double> phi_step;  // default 0.0005 (new campaigns); must match otherwise
};

/// What one `jam campaign import` did.
struct ImportOutcome {
  int imported = 0, already = 0, repaired = 0;
  std::vector<SetAside> set_aside;  // this import's
  std::vector<std::string> notes;   // what else it did: sample ids given, files adopted, repairs
};

/// Imports `files` into `directory` (created when absent; else it must be an external
/// campaign, or what an interrupted first import left) under the campaign's lock, then rewrites
/// external.toml atomically (campaign/external_import.cpp).
ImportOutcome import_runs(const std::string& directory, const std::vector<std::string>& files,
                          const ImportOptions& options);

/// Why runs/<run.name>.h5 of `directory` cannot be used ("" when it can): it must read as an
/// open run and still have the checksum it was imported with. The run read goes to *read.
std::string stored_run_problem(const std::string& directory, const ExternalRun& run,
                               OpenRun* read = nullptr);

/// `jam campaign status` of an external campaign: runs per ensemble, and the files set aside.
/// Returns the exit status (0; 1 when a stored run no longer reads).
int print_external_status(const std::string& directory, bool json);

}  // namespace jam
