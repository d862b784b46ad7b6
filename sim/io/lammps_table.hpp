#pragma once
// A contact law as a LAMMPS pair_style table file: one section per pair type (SS, SB, BB),
// each "N points R r_lo d" followed by rows "k r U(r) f(r)", from the law's energy_at and
// force_at (sim/model/contact_law.hpp). The LAMMPS cross-checks write it next to their input,
// so LAMMPS always runs the law jam runs. Numbers are written in their shortest round-trip form.
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "sim/io/atomic_file.hpp"
#include "sim/model/contact_laws.hpp"

namespace jam {

/// The table text for diameter ratio `ratio` (small diameter 1). Rows run from r = 0.4 d
/// (overlaps deeper than 60% never occur in a stable run) to r = d, where U = f = 0.
template <ContactLaw Law>
std::string lammps_table(double ratio) {
  std::string out =
      fmt::format("# {} contact {}, diameter ratio {}\n", Law::kName, Law::kFormula, ratio);
  out += "# written by jam (sim/io/lammps_table.hpp)\n";
  const int points = Law::kTablePoints;
  const struct {
    const char* name;
    double d;
  } pairs[] = {{"SS", 1.0}, {"SB", 0.5 * (1.0 + ratio)}, {"BB", ratio}};
  for (const auto& [name, d] : pairs) {
    const double lo = 0.4 * d;
    out += fmt::format("\n{}\nN {} R {} {}\n\n", name, points, lo, d);
    for (int k = 0; k < points; ++k) {
      const double r = k < points - 1 ? lo + (d - lo) * k / (points - 1) : d;
      out += fmt::format("{} {} {} {}\n", k + 1, r, Law::energy_at(r, d), Law::force_at(r, d));
    }
  }
  return out;
}

/// What a LAMMPS input needs of the law: the table file written and the pair_style table
/// interpolation it asks for.
struct LammpsTableFile {
  std::string file;   // "<law>_contact.table"
  std::string style;  // "linear" or "spline": pair_style table <style> 100000
  std::string text;   // the table
};

/// The table of the law named `contact` (throws std::invalid_argument for an unknown name).
inline LammpsTableFile lammps_table_for(const std::string& contact, double ratio) {
  return with_contact_law(contact, [&]<class Law>() {
    return LammpsTableFile{std::string(Law::kName) + "_contact.table", Law::kLammpsTableStyle,
                           lammps_table<Law>(ratio)};
  });
}

/// Writes the table of the law named `contact` into dir, atomically; returns what was written.
inline LammpsTableFile write_lammps_table(const std::filesystem::path& dir,
                                          const std::string& contact, double ratio) {
  LammpsTableFile t = lammps_table_for(contact, ratio);
  AtomicFile f((dir / t.file).string());
  std::fwrite(t.text.data(), 1, t.text.size(), f.stream());
  f.commit();
  return t;
}

}  // namespace jam
