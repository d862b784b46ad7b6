#pragma once
// A LAMMPS log of any input, as a table: the thermo columns a caller names, every thermo row
// under a header that has them (all runs of the log, the row LAMMPS repeats at the boundary of
// two runs taken once), the runs it reports, and the settings the log states literally: its
// version, `dimension`, `timestep`, each `fix deform` (lammps_deform.hpp) and the atoms created
// or read. Values must be whole finite numbers; anything else is one line naming the file, line,
// column and value.
//
// LAMMPS echoes a command as written and, with a variable in it, once more after each
// substitution, on the lines right after: consecutive `fix deform` lines of one fix ID are one
// command, the last of them the one LAMMPS ran.
#include <cstdint>
#include <filesystem>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sim/io/lammps_deform.hpp"

namespace jam {

struct LammpsLog {
  std::string version;  // "2 Aug 2023 - Update 3" from the first line "LAMMPS (...)"
  std::optional<int> dim;
  std::optional<double> timestep;
  std::optional<double> rate;         // -trate of the last fix deform showing it (> 0)
  std::optional<std::int64_t> atoms;  // "Created N atoms" or read_data's "N atoms"
  std::vector<std::string> header;    // the thermo header the rows were read under
  std::map<std::string, std::vector<double>> columns;  // the named columns, one entry per row
  std::vector<int> lines;                              // the log line of each row
  std::vector<LammpsDeform> deforms;                   // every fix deform, in the log's order
  // Each run the log reports: the line of its thermo header when its rows were read, else of
  // its "Loop time" line (a run under another header, a minimization).
  std::vector<int> runs;
};

/// The blank-separated words of a line.
std::vector<std::string> lammps_words(const std::string& line);

/// The whole of `text` as a finite number, else one line naming where, the field and the value.
double lammps_number(const std::string& text, const std::string& where, const std::string& field);

/// The whole of `text` as a whole number in [0, kMaxExactWhole] (whole_number.hpp: the largest
/// count a log may state, atoms or steps), else one line naming where, the field and the value.
std::int64_t lammps_count(const std::string& text, const std::string& where,
                          const std::string& field);

/// Reads `path`; `columns` are thermo column names as LAMMPS prints them (Step, Time, PotEng,
/// Volume, c_virial, v_Z, ...). Throws std::runtime_error when none of its headers has them
/// all, or a row under such a header is not a row of numbers.
LammpsLog read_lammps_log(const std::string& path, const std::vector<std::string>& columns);

/// The same from a stream; `name` stands for the file in messages.
LammpsLog read_lammps_log(std::istream& in, const std::string& name,
                          const std::vector<std::string>& columns);

/// Why a LAMMPS process failed, in one line for a message: the first line naming an error
/// ("ERROR: ...", "ERROR on proc 0: ...", Open MPI's "ORTE_ERROR_LOG: ...") in its log, else in
/// its error output (where Open MPI's start-up failures go), with control characters shown as
/// '?' and at most 240 characters; else a sentence saying that neither names one.
std::string lammps_failure_reason(const std::string& log, const std::string& error_output);

/// Runs an lmp (or mpirun lmp) argument vector in `dir` whose log is dir/`log`: its screen
/// discarded, its error output kept in dir/`log`.stderr, an Open MPI session directory of its
/// own (sim/io/process.hpp). Throws std::runtime_error with lammps_failure_reason when it fails.
void run_lammps_process(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                        const std::string& log);

}  // namespace jam
