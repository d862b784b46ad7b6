#pragma once
// LAMMPS data files, atom_style atomic: type 1 = small, type 2 = big. The box is written
// centred on the origin, [-L/2, L/2] per side (in 2D the z bounds are -0.5 0.5 and z = 0),
// which is also the origin of the host flow v_host = -rate r, so that LAMMPS's
// fix deform ... trate, which shrinks the box about its centre, follows the same affine map.
#include <cstdint>
#include <istream>
#include <string>
#include <utility>
#include <vector>

#include "sim/model/particles.hpp"

namespace jam {

template <int D>
struct LammpsData {
  ParticleData<D> particles;
  double box_length = 0.0;
};

/// Writes atomically (temporary name, then rename). Masses per type are written as given.
template <int D>
void write_lammps_data(const std::string& path, const ParticleData<D>& particles, double box_length,
                       double mass_small, double mass_big, const std::string& title);

/// Reads a data file; errors name the file, the line and the field. The box must be square
/// (cubic), orthogonal, and in 2D have z = 0 for every atom.
template <int D>
LammpsData<D> read_lammps_data(const std::string& path);

/// The same from a stream; `path` names it in the errors.
template <int D>
LammpsData<D> read_lammps_data(std::istream& in, const std::string& path);

/// The command line of `lmp` on an input script: `lmp -log LOG -screen none -in INPUT` and
/// `-var NAME VALUE` for each variable, as an argument vector (sim/io/process.hpp).
std::vector<std::string> lammps_command_line(
    const std::string& log, const std::string& input,
    const std::vector<std::pair<std::string, std::string>>& variables);

/// The variables every reference/lammps input takes for the paper's species and neighbor list:
/// gamma_s = k_d V_s = 2/D, drag_ratio = V_b/V_s = 1.4^D, d_sb = 1.2, d_bb = 1.4, skin 0.3.
std::vector<std::pair<std::string, std::string>> lammps_species_variables(int dim);

}  // namespace jam
