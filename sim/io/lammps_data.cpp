#include "sim/io/lammps_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <unordered_set>
#include <vector>

#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/whole_number.hpp"

namespace jam {

namespace {
/// The data file's text into f; fmt throws std::system_error when a write fails.
template <int D>
void write_lammps_data_to(std::FILE* f, const ParticleData<D>& p, double box_length,
                          double mass_small, double mass_big, const std::string& title);
}  // namespace

template <int D>
void write_lammps_data(const std::string& path, const ParticleData<D>& p, double box_length,
                       double mass_small, double mass_big, const std::string& title) {
  AtomicFile out(path);
  try {
    write_lammps_data_to(out.stream(), p, box_length, mass_small, mass_big, title);
  } catch (const std::system_error& e) {
    // fmt's "cannot write to file" names no file; the temporary still holds the space it took,
    // so write_failure sees the disk as full as it was.
    throw WriteError(
        fmt::format("cannot write '{}': {}", path, write_failure(path, e.code().value())));
  }
  out.commit();
}

namespace {
template <int D>
void write_lammps_data_to(std::FILE* f, const ParticleData<D>& p, double box_length,
                          double mass_small, double mass_big, const std::string& title) {
  const double half = 0.5 * box_length;
  fmt::print(f, "LAMMPS data file: {}\n\n{} atoms\n2 atom types\n\n", title, p.size());
  const char* axes[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) {
    if (d < D) {
      fmt::print(f, "{:.17g} {:.17g} {}lo {}hi\n", -half, half, axes[d], axes[d]);
    } else {
      fmt::print(f, "-0.5 0.5 zlo zhi\n");
    }
  }
  fmt::print(f, "\nMasses\n\n1 {:.17g}\n2 {:.17g}\n\nAtoms # atomic\n\n", mass_small, mass_big);
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return p.id[a] < p.id[b]; });
  for (std::size_t i : order) {
    fmt::print(f, "{} {}", p.id[i], p.type[i] + 1);
    for (int d = 0; d < 3; ++d) {
      fmt::print(f, " {:.17g}", d < D ? box_length * (p.s[d][i] - 0.5) : 0.0);
    }
    fmt::print(f, " 0 0 0\n");
  }
}
}  // namespace

namespace {

constexpr long long kMaxAtoms = std::int64_t{1} << 31;  // as jam sim --n

struct Reader {
  std::string path;
  int line_no = 0;

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("{}:{}: {}", path, line_no, what));
  }

  /// A finite number, the whole token (std::from_chars: correctly rounded, as strtod, without
  /// the locale; a leading '+' is accepted, as strtod does).
  double number(std::string_view token, std::string_view field) const {
    std::string_view digits = token;
    if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
    double v = 0.0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (error == std::errc::invalid_argument) {
      fail(fmt::format("{}: '{}' is not a number", field, token));
    }
    if (error != std::errc{} || end != digits.data() + digits.size() || !std::isfinite(v)) {
      fail(fmt::format("{}: '{}' is not a finite number", field, token));
    }
    return v;
  }

  long long integer(std::string_view token, std::string_view field) const {
    const auto v = whole_number(number(token, field), -kMaxExactWhole, kMaxExactWhole);
    if (!v) fail(fmt::format("{}: '{}' is not an integer", field, token));
    return *v;
  }
};

/// The line's whitespace-separated words before any '#' (views into `line`), into `t`.
const std::vector<std::string_view>& tokens(std::string_view line,
                                            std::vector<std::string_view>& t) {
  line = line.substr(0, line.find('#'));
  // isspace in the C locale
  const auto space = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };
  t.clear();
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && space(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !space(line[i])) ++i;
    if (i > begin) t.push_back(line.substr(begin, i - begin));
  }
  return t;
}

}  // namespace

template <int D>
LammpsData<D> read_lammps_data(const std::string& path) {
  check_input_file("--read-lammps-data", path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("--read-lammps-data {}: cannot open file", path));
  return read_lammps_data<D>(in, path);
}

template <int D>
LammpsData<D> read_lammps_data(std::istream& in, const std::string& path) {
  Reader r{path};
  std::string line;
  std::getline(in, line);  // title line
  r.line_no = 1;

  long long natoms = -1, ntypes = -1;
  std::array<double, 3> lo{}, hi{};
  std::array<bool, 3> have_bounds{};
  LammpsData<D> data;
  bool have_atoms = false;
  std::vector<std::string_view> words, scratch;  // a line's words, kept between lines
  while (std::getline(in, line)) {
    ++r.line_no;
    const auto& t = tokens(line, words);
    if (t.empty()) continue;
    if (t.size() == 2 && t[1] == "atoms") {
      natoms = r.integer(t[0], "atoms");
      if (natoms < 0) r.fail(fmt::format("atoms: {} (a count must be >= 0)", t[0]));
    } else if (t.size() == 3 && t[1] == "atom" && t[2] == "types") {
      ntypes = r.integer(t[0], "atom types");
      if (ntypes < 0) r.fail(fmt::format("atom types: {} (a count must be >= 0)", t[0]));
    } else if (t.size() == 4 && t[2].size() == 3 && t[2].substr(1) == "lo" &&
               t[3].substr(1) == "hi") {
      const int axis = t[2][0] - 'x';
      if (axis < 0 || axis > 2) r.fail(fmt::format("unknown box bound '{}'", t[2]));
      lo[axis] = r.number(t[0], t[2]);
      hi[axis] = r.number(t[1], t[3]);
      if (!(hi[axis] > lo[axis])) r.fail(fmt::format("{} {}: empty box", t[2], t[3]));
      have_bounds[axis] = true;
    } else if (t.size() >= 3 && t.back() == "yz") {
      r.fail("triclinic boxes (xy xz yz) are not supported");
    } else if (t[0] == "Masses" || t[0] == "Velocities") {
      // Masses follow from the quality factor, velocities start at zero: skip the section.
      std::getline(in, line);
      ++r.line_no;
      while (std::getline(in, line)) {
        ++r.line_no;
        if (tokens(line, scratch).empty()) break;
      }
    } else if (t[0] == "Atoms") {
      if (t.size() > 1 && t[1] != "atomic") {
        r.fail(fmt::format("Atoms section style '{}': only atomic is supported", t[1]));
      }
      if (natoms < 0) r.fail("Atoms section before the 'atoms' count");
      if (natoms < 2) r.fail(fmt::format("atoms: {} (at least 2 are needed)", natoms));
      if (natoms > kMaxAtoms) r.fail(fmt::format("atoms: {} (at most {})", natoms, kMaxAtoms));
      if (have_atoms) r.fail("a second Atoms section");
      for (int d = 0; d < D; ++d) {
        if (!have_bounds[d]) r.fail(fmt::format("missing {}lo {}hi line", "xyz"[d], "xyz"[d]));
      }
      const double length = hi[0] - lo[0];
      if (!std::isfinite(length))
        r.fail(fmt::format("xlo xhi: box length {} is not finite", length));
      for (int d = 1; d < D; ++d) {
        if (std::abs((hi[d] - lo[d]) - length) > 1e-12 * length) {
          r.fail(fmt::format("box is not square/cubic: side {} is {} but x is {}", "xyz"[d],
                             hi[d] - lo[d], length));
        }
      }
      data.box_length = length;
      // Memory grows with the atom lines actually read, never with the count a header claims.
      std::unordered_set<long long> seen;
      std::getline(in, line);  // blank line after the header
      ++r.line_no;
      if (!tokens(line, scratch).empty()) r.fail("expected a blank line after 'Atoms'");
      for (long long k = 0; k < natoms; ++k) {
        if (!std::getline(in, line)) {
          r.fail(fmt::format("file ends after {} of {} atoms", k, natoms));
        }
        ++r.line_no;
        const auto& a = tokens(line, scratch);
        if (a.size() != 5 && a.size() != 8) {
          r.fail(fmt::format("atom line has {} fields, expected 'id type x y z [ix iy iz]'",
                             a.size()));
        }
        const long long id = r.integer(a[0], "atom id");
        if (id < 1 || id > natoms || !seen.insert(id).second) {
          r.fail(fmt::format("atom id: {} is out of range or repeated", a[0]));
        }
        const long long type = r.integer(a[1], "atom type");
        if (type != 1 && type != 2) r.fail(fmt::format("atom type: {} (must be 1 or 2)", a[1]));
        const std::size_t i = static_cast<std::size_t>(k);
        data.particles.resize(i + 1);
        data.particles.id[i] = static_cast<std::uint32_t>(id);
        data.particles.type[i] = static_cast<std::uint8_t>(type - 1);
        for (int d = 0; d < 3; ++d) {
          const double x = r.number(a[2 + d], std::string_view("xyz").substr(d, 1));
          if (d < D) {
            const double scaled = (x - lo[d]) / length;
            if (!std::isfinite(scaled) || std::abs(scaled) > 1e6) {
              r.fail(fmt::format("{}: {} is far outside the box", "xyz"[d], a[2 + d]));
            }
            data.particles.s[d][i] = wrap_unit(scaled);
          } else if (x != 0.0) {
            r.fail(fmt::format("z: {} (a 2D configuration needs z = 0)", a[2 + d]));
          }
        }
      }
      have_atoms = true;
    } else {
      // Sections this project never writes would silently change the model: refuse them.
      if (std::isupper(static_cast<unsigned char>(t[0][0]))) {
        r.fail(fmt::format("unsupported section '{}'", t[0]));
      }
      r.fail(fmt::format("unrecognised header line '{}'", line));
    }
  }
  if (!have_atoms) r.fail("no Atoms section");
  if (ntypes > 2) {
    throw std::runtime_error(fmt::format("{}: atom types: {} (at most 2)", path, ntypes));
  }
  return data;
}

template void write_lammps_data<2>(const std::string&, const ParticleData<2>&, double, double,
                                   double, const std::string&);
template void write_lammps_data<3>(const std::string&, const ParticleData<3>&, double, double,
                                   double, const std::string&);
template LammpsData<2> read_lammps_data<2>(const std::string&);
template LammpsData<3> read_lammps_data<3>(const std::string&);
template LammpsData<2> read_lammps_data<2>(std::istream&, const std::string&);
template LammpsData<3> read_lammps_data<3>(std::istream&, const std::string&);

std::vector<std::string> lammps_command_line(
    const std::string& log, const std::string& input,
    const std::vector<std::pair<std::string, std::string>>& variables) {
  std::vector<std::string> argv = {"lmp", "-log", log, "-screen", "none", "-in", input};
  for (const auto& [name, value] : variables) argv.insert(argv.end(), {"-var", name, value});
  return argv;
}

std::vector<std::pair<std::string, std::string>> lammps_species_variables(int dim) {
  auto g = [](double v) { return fmt::format("{:.17g}", v); };
  return {{"skin", "0.3"},
          {"gamma_s", g(2.0 / dim)},
          {"drag_ratio", g(std::pow(1.4, dim))},
          {"d_sb", "1.2"},
          {"d_bb", "1.4"}};
}

}  // namespace jam
