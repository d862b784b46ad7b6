#pragma once
// A campaign directory:
//   <output>/campaign.toml        the campaign file the directory was last run with
//   <output>/manifest.toml        the plan as run, and per-run status and cost (manifest.hpp)
//   <output>/runs/<name>.h5       one run file per finished run (sim schema)
//   <output>/runs/<name>.h5.checkpoint   state of an unfinished run
//   <output>/runs/<name>.record   status of the last attempt (TOML: status, wall time, ...)
//   <output>/starts/n<N>_phi<phi>_s<k>.h5   relaxed start shared by every rate of a sample
//   <output>/chain/<name>.start.h5   chained start of run <name> (chain_phi_init), left by the
//                                    next faster run of its sample
// Every file is written atomically, so the directory is consistent after any interruption.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "campaign/campaign_file.hpp"
#include "campaign/run_plan.hpp"
#include "sim/run/thread_cpu_clock.hpp"

namespace jam {

enum class RunStatus { kDone, kPartial, kFailed, kCorrupt, kMissing };

const char* to_string(RunStatus s);

/// Creates the directory, or checks that the campaign is compatible with the one it was run
/// with (only sizes, phi_init, log10_rates and samples may change), then stores the campaign.
void prepare_campaign_directory(const Campaign& campaign);

/// Removes the temporary files ("*.partial", atomic_file.hpp) that processes killed while
/// writing left in the directory, runs/ and starts/. Only the directory's owner (the holder of
/// its CampaignLock) may call it: nobody else can be writing them.
void remove_stale_temporaries(const std::string& directory);

/// The campaign a directory was last run with.
Campaign stored_campaign(const std::string& directory);

/// Classifies one run from the files present. A run file that cannot be read or is not
/// marked complete is kCorrupt and is never taken for a result.
RunStatus run_status(const PlannedRun& run, std::string* detail = nullptr);

/// run_status's classification of the run file at `file` (its checkpoint and record beside
/// it), its identity judged by `identity_problem` ("" when the file is the expected run's,
/// else what differs; it is called only for a sound file).
RunStatus classify_run_file(const std::string& file,
                            const std::function<std::string()>& identity_problem,
                            std::string* detail);

/// Writes path atomically, and not at all when it already holds text: its time then says when
/// its content last changed (jam pipeline redoes later stages by such times).
void write_text_if_changed(const std::string& path, const std::string& text);

struct RunRecord {
  std::string status;  // "done" or "failed"
  double wall_seconds = 0.0;
  // CPU seconds of the thread that ran it (campaign runs are single-threaded): its cost in
  // core-seconds, which other work on a shared machine does not inflate as it does the wall.
  // A run resumed from its checkpoint adds those of its earlier attempts (checkpointed since
  // 2026-11-27; an older checkpoint's are not known, and the record then holds less).
  double cpu_seconds = 0.0;
  std::int64_t steps = 0;
  // Force evaluations x N (the jamming search's included), the planner's unit: a resumed
  // campaign's ETA starts from their ratio to the plan. 0 in records written before
  // 2026-11-27 and of runs resumed from a checkpoint (the earlier attempts' are not known).
  std::int64_t particle_steps = 0;
  std::string error;
  std::string version;  // of the jam that wrote it (read back; written as kVersion)
};

void write_run_record(const PlannedRun& run, const RunRecord& record);

/// The record of the run's last attempt (nullopt: none, or not readable).
std::optional<RunRecord> read_run_record(const PlannedRun& run);

/// The record at `path` (<output>/runs/<name>.record; nullopt: none, or not readable).
std::optional<RunRecord> read_run_record_at(const std::string& path);

/// The core-seconds the run's last attempt recorded: its CPU seconds, or its wall seconds in
/// records written before they carried CPU seconds (nullopt: no readable record).
std::optional<double> recorded_core_seconds(const PlannedRun& run);

}  // namespace jam
