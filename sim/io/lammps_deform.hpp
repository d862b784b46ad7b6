#pragma once
// The box deformation a LAMMPS log states (`fix ID group deform N parameter style args ...`), and
// what an import may conclude from it. The model is an isotropic compression at one rate:
// L(t) = L0 exp(-rate t) along every axis. A deform that moves one axis alone, or each axis
// differently, is another protocol; a log of several runs or several deforms (a relaxation
// before the compression, a rate changed between runs) has no single rate, so its packing
// cannot follow from the time.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace jam {

/// One `fix ... deform` command as the log shows it.
struct LammpsDeform {
  int line = 0;    // its line in the log (the last of its echoes, see lammps_log.hpp)
  std::string id;  // the fix ID
  // Each parameter it names (x, y, z, xy, xz, yz) -> its style (trate, final, erate, ...).
  std::map<std::string, std::string> styles;
  // Each parameter of style trate whose value the log shows literally -> that value
  // (negative: a compression); one given through an unsubstituted variable is absent.
  std::map<std::string, double> trates;
};

/// The deform command of the words `w` of a log line ("fix" ID group "deform"|"deform/..." ...),
/// else nullopt. A literal trate must be a compression of a rate jam simulates (-1 <= trate <=
/// -1e-12), else std::runtime_error naming `where`.
std::optional<LammpsDeform> parse_lammps_deform(const std::vector<std::string>& w, int line,
                                                const std::string& where);

/// Every deform of the log is an isotropic compression at one rate: it names exactly the box's
/// axes (x, y, and z in 3D), no tilt, each with the same style (and the same trate where the
/// log shows it), and every literal trate of the log is the same. Else std::runtime_error:
/// "LOG:LINE: ..." naming the deform.
void check_isotropic_deforms(const std::vector<LammpsDeform>& deforms, int dim,
                             const std::string& log);

/// The packing from the time and the log's rate, phi_init exp(D rate t), holds only for a log of
/// one run under one deform whose trate the log shows, defined before the first thermo row
/// (`first_row`: its line). `runs`: the line of each run (lammps_log.hpp). Else
/// std::runtime_error: "LOG:LINE: ...; name a volume or packing_fraction column ...".
void check_packing_from_time(const std::vector<LammpsDeform>& deforms, const std::vector<int>& runs,
                             int first_row, const std::string& log);

}  // namespace jam
