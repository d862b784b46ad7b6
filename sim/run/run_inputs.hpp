#pragma once
// What a compression run reads and writes before any work: the start it compresses (random,
// a LAMMPS data file or a chained start) and the output paths it will write, checked first.
#include <fmt/format.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/initial_state.hpp"
#include "sim/io/chain_start.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/model/particles.hpp"
#include "sim/model/species.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {

/// Fails early, before any work, if the output is not a regular file or a new name
/// (output_path.hpp) or cannot be written; returns the path to write (a link's target).
std::string checked_writable(const std::string& option, const std::string& path);

template <int D>
struct Start {
  ParticleData<D> particles;
  double box_length = 0.0;
  std::string description;
};

/// The start of a run as the config names it.
template <int D>
Start<D> make_start(const SimConfig& c, const Species<D>& species) {
  Start<D> start;
  if (!c.read_start.empty()) {
    ChainStart<D> chained;
    try {
      chained = read_chain_start<D>(c.read_start, c.start_identity);
    } catch (const std::runtime_error& e) {
      throw ConfigError(fmt::format("--read-start {}: {}", c.read_start, e.what()));
    }
    if (static_cast<std::int64_t>(chained.particles.size()) != c.n) {
      throw ConfigError(fmt::format("--read-start {}: holds {} particles, not --n {}", c.read_start,
                                    chained.particles.size(), c.n));
    }
    start.particles = std::move(chained.particles);
    start.box_length = chained.box_length;
    // Named by its identity, not its path: a campaign's run files do not depend on where the
    // directory is.
    start.description = "chained start " + chain_start_key(chained.identity);
  } else if (!c.read_lammps_data.empty()) {
    LammpsData<D> data = read_lammps_data<D>(c.read_lammps_data);
    start.particles = std::move(data.particles);
    start.box_length = data.box_length;
    start.description = c.read_lammps_data;
    sort_spatially(start.particles, species, start.box_length);
  } else {
    RandomStart<D> r = random_start<D>(static_cast<std::size_t>(c.n), c.seed, species, c.phi_init);
    start.particles = std::move(r.particles);
    start.box_length = r.box_length;
    start.description = "random";
  }
  return start;
}

}  // namespace jam
