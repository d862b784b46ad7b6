#include "sim/io/lammps_log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "sim/io/output_path.hpp"
#include "sim/io/process.hpp"
#include "sim/io/whole_number.hpp"

namespace jam {
namespace {

bool literal(const std::string& word) {
  return !word.empty() && word[0] != '$' && word[0] != 'v' && word.find("${") == std::string::npos;
}

/// Atoms created or read add up; their sum stays a count too.
void add_atoms(std::int64_t atoms, const std::string& where, LammpsLog& log) {
  const std::int64_t total = log.atoms.value_or(0) + atoms;  // both <= 2^53: no overflow
  if (total > kMaxExactWhole)
    throw std::runtime_error(fmt::format("{}: {} atoms in all (at most 2^53)", where, total));
  log.atoms = total;
}

/// A fix deform command; the echo of the same command after a substitution (the line right
/// after, same fix ID) replaces it.
void add_deform(LammpsDeform d, int previous_line, LammpsLog& log) {
  if (!log.deforms.empty() && log.deforms.back().line == previous_line &&
      log.deforms.back().id == d.id)
    log.deforms.back() = std::move(d);
  else
    log.deforms.push_back(std::move(d));
  for (const LammpsDeform& c : log.deforms)
    if (!c.trates.empty()) log.rate = -c.trates.begin()->second;
}

/// The settings a log states literally (a value given through a variable is echoed with it
/// substituted when LAMMPS runs with `-echo log`, and not otherwise). `previous_line`: the
/// line number of the last non-blank line before this one.
void read_setting(const std::vector<std::string>& w, const std::string& where, int line,
                  int previous_line, LammpsLog& log) {
  if (w[0] == "dimension" && w.size() == 2 && literal(w[1])) {
    const double dim = lammps_number(w[1], where, "dimension");
    if (dim != 2 && dim != 3)
      throw std::runtime_error(fmt::format("{}: dimension {} (must be 2 or 3)", where, w[1]));
    log.dim = static_cast<int>(dim);
  } else if (w[0] == "timestep" && w.size() == 2 && literal(w[1])) {
    log.timestep = lammps_number(w[1], where, "timestep");
    if (!(*log.timestep > 0))
      throw std::runtime_error(fmt::format("{}: timestep {} (must be > 0)", where, w[1]));
  } else if (auto deform = parse_lammps_deform(w, line, where)) {
    add_deform(std::move(*deform), previous_line, log);
  } else if (w.size() == 3 && w[0] == "Created" && w[2] == "atoms") {
    add_atoms(lammps_count(w[1], where, "created atoms"), where, log);
  } else if (w.size() == 2 && w[1] == "atoms" &&
             std::isdigit(static_cast<unsigned char>(w[0][0]))) {
    add_atoms(lammps_count(w[0], where, "atoms read"), where, log);
  }
}

bool has_all(const std::vector<std::string>& header, const std::vector<std::string>& names) {
  return std::all_of(names.begin(), names.end(), [&](const std::string& n) {
    return std::find(header.begin(), header.end(), n) != header.end();
  });
}

/// The first line of `path` holding "ERROR", shown safely; "" when there is none (or no file).
std::string first_error_line(const std::string& path) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.find("ERROR") == std::string::npos) continue;
    constexpr std::size_t kLongest = 240;
    if (line.size() > kLongest) line = line.substr(0, kLongest) + "...";
    for (char& c : line)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return line;
  }
  return "";
}

}  // namespace

std::string lammps_failure_reason(const std::string& log, const std::string& error_output) {
  for (const std::string& file : {log, error_output}) {
    if (std::string line = first_error_line(file); !line.empty()) return line;
  }
  return "neither its log nor its error output names an error";
}

void run_lammps_process(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                        const std::string& log) {
  ProcessOptions where;
  where.working_directory = dir;
  where.stdout_file = "/dev/null";
  where.stderr_file = (dir / (log + ".stderr")).string();
  where.mpi_program = true;
  if (const int status = run_program(argv, where); status != 0) {
    throw std::runtime_error(fmt::format(
        "lmp failed (exit status {}): {}; see {}", status,
        lammps_failure_reason((dir / log).string(), where.stderr_file), (dir / log).string()));
  }
}

std::vector<std::string> lammps_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

double lammps_number(const std::string& text, const std::string& where, const std::string& field) {
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, v);
  if (error != std::errc() || at != end)
    throw std::runtime_error(fmt::format("{}: {} '{}' is not a number", where, field, text));
  if (!std::isfinite(v))
    throw std::runtime_error(fmt::format("{}: {} {} is not finite", where, field, text));
  return v;
}

std::int64_t lammps_count(const std::string& text, const std::string& where,
                          const std::string& field) {
  if (const auto count = whole_number(lammps_number(text, where, field), 0, kMaxExactWhole))
    return *count;
  throw std::runtime_error(
      fmt::format("{}: {} {} is not a whole number in [0, 2^53]", where, field, text));
}

LammpsLog read_lammps_log(const std::string& path, const std::vector<std::string>& columns) {
  check_input_file("LAMMPS log", path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read LAMMPS log", path));
  return read_lammps_log(in, path, columns);
}

LammpsLog read_lammps_log(std::istream& in, const std::string& path,
                          const std::vector<std::string>& columns) {
  LammpsLog log;
  for (const auto& c : columns) log.columns[c];
  std::vector<std::string> header;  // the current block's, when it has every column
  std::vector<std::size_t> index;   // of each named column in it
  std::optional<double> last_step;
  std::size_t rows_in_block = 0;
  int header_line = 0, previous_line = 0;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const auto w = lammps_words(line);
    if (w.empty()) continue;
    const int previous = std::exchange(previous_line, line_no);
    const std::string where = fmt::format("{}:{}", path, line_no);
    // The end of a run whose rows are not read (a run's own end is taken below).
    const bool loop = w[0] == "Loop" && w.size() > 1 && w[1] == "time";
    if (loop && (header.empty() || rows_in_block == 0)) log.runs.push_back(line_no);
    if (line_no == 1 && w[0] == "LAMMPS" && line.find('(') != std::string::npos) {
      const auto open = line.find('('), close = line.rfind(')');
      log.version = line.substr(open + 1, close > open ? close - open - 1 : std::string::npos);
    }
    if (header.empty()) {
      read_setting(w, where, line_no, previous, log);
      if (has_all(w, columns) && !std::isdigit(static_cast<unsigned char>(w[0][0]))) {
        header = w;
        header_line = line_no;
        index.clear();
        for (const auto& c : columns)
          index.push_back(static_cast<std::size_t>(std::find(w.begin(), w.end(), c) - w.begin()));
        rows_in_block = 0;
      }
      continue;
    }
    if (w[0] == "Loop" || w[0] == "ERROR:") {  // the block's end
      header.clear();
      continue;
    }
    if (w[0] == "WARNING:") continue;  // LAMMPS may warn between thermo rows
    // A line that names the columns but has no rows of numbers under it (the echo of a
    // thermo_style command) was no header: read it again as a setting.
    const bool numbers = std::all_of(w.begin(), w.end(), [](const std::string& x) {
      double v;
      const auto [at, error] = std::from_chars(x.data(), x.data() + x.size(), v);
      return error == std::errc() && at == x.data() + x.size();
    });
    if (rows_in_block == 0 && (w.size() != header.size() || !numbers)) {
      header.clear();
      read_setting(w, where, line_no, previous, log);
      continue;
    }
    if (w.size() != header.size())
      throw std::runtime_error(fmt::format("{}: thermo row has {} columns, its header {}", where,
                                           w.size(), header.size()));
    if (++rows_in_block == 1) log.header = header, log.runs.push_back(header_line);
    // The first row of a run repeats the last of the run before it.
    const auto step = std::find(header.begin(), header.end(), "Step");
    if (step != header.end()) {
      const double s =
          lammps_number(w[static_cast<std::size_t>(step - header.begin())], where, "Step");
      if (last_step && s == *last_step) continue;
      last_step = s;
    }
    for (std::size_t k = 0; k < columns.size(); ++k)
      log.columns[columns[k]].push_back(lammps_number(w[index[k]], where, columns[k]));
    log.lines.push_back(line_no);
  }
  if (log.header.empty()) {
    std::string names;
    for (const auto& c : columns) names += (names.empty() ? "" : " ") + c;
    throw std::runtime_error(
        fmt::format("{}: no thermo header with the columns {} (name them as LAMMPS prints them)",
                    path, names));
  }
  return log;
}

}  // namespace jam
