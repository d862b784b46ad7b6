#pragma once
// The staleness rules of `jam pipeline FILE` (app/pipeline_command.cpp): each stage is redone
// only when its inputs changed since it was last made: stats.h5 when it no longer describes
// the campaign's runs (stats/stats_inputs.hpp) or its fit the verdicts declared to it;
// checks.json when stats.h5 or the campaign file is newer, or the options differ from those it
// records (check_record); the report when checks.json or stats.h5 is newer.
#include <filesystem>
#include <string>
#include <vector>

#include "design/judging_options.hpp"

namespace jam::design {

using FileTime = std::filesystem::file_time_type;

/// The file's modification time; the earliest time when it cannot be read.
FileTime modified(const std::filesystem::path& p);

/// Whether `output` is missing or older than `input`.
bool stale(const std::filesystem::path& output, FileTime input);

/// stats.h5 of each averaged campaign, unless it still describes that campaign's runs (the
/// same definition `jam check` refuses by) and its fit the verdicts declared to it; a stop
/// asked for ends it before the next (Interrupted).
void average_unless_current(const std::vector<std::filesystem::path>& averaged);

/// `check all` of `dir` (no table: the report's summary prints it), when stats.h5 or the
/// campaign file is newer than checks.json (or a compared campaign's stats.h5 is) or the
/// options differ from those it records.
void judge_unless_up_to_date(const std::filesystem::path& dir, const JudgingArgs& judging,
                             const std::vector<std::string>& compare_with);

}  // namespace jam::design
