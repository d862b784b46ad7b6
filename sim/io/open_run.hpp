#pragma once
// The open run format (docs/cross-simulator.md): the least a compression run of another
// simulator must carry for jam to average, check and report it. jam's own run files are a
// superset and read through the same door. Everything the spec states is checked on reading
// and before writing, shape before value, with one line naming the file, the field and the
// value; an importer writes through write_open_run and so can never publish a run that the
// readers would refuse.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace jam {

inline constexpr const char* kOpenRunFormat = "jam-open-run";
inline constexpr std::int64_t kOpenRunFormatVersion = 1;
inline constexpr const char* kOpenRunProtocol = "isotropic-compression";

struct OpenRun {
  // The model and the run (root attributes).
  int dim = 0;
  std::int64_t n = 0;
  double diameter_ratio = 1.4;
  std::string contact = "harmonic";
  std::string dynamics = "overdamped";
  double q = 0.0;  // inertial only
  double compression_rate = 0.0, phi_init = 0.0;
  std::string simulator, simulator_version;
  std::int64_t sample = 0;
  std::optional<double> jamming_packing_fraction;
  std::string source, source_checksum, interpolation;  // provenance, may be empty
  bool jam_native = false;                             // a run file of jam's own (read only)
  // One entry per output point (empty: not stored).
  std::vector<double> packing_fraction, pressure, contacts_per_particle, energy_per_particle,
      time;
};

/// Checks r against the spec; throws std::runtime_error "<where>: <field> <value> ...".
void validate_open_run(const OpenRun& r, const std::string& where);

/// The model's part of it alone (dim, n, diameter_ratio, contact, dynamics, q), for records
/// that hold a run's model without its series (external.toml).
void validate_open_run_model(const OpenRun& r, const std::string& where);

/// Reads and checks an open run, or a run file of jam's own (recognised by its `checksum`,
/// which is verified; simulator "jam"). Throws std::runtime_error naming file and field.
OpenRun read_open_run(const std::string& path);

/// Checks r, then writes it to path through a temporary renamed when complete (the path must
/// be a regular file or absent: output_path.hpp). Nothing is left behind on error.
void write_open_run(const std::string& path, const OpenRun& r);

/// FNV-1a (64 bit) of a file's bytes as 16 hex digits: the `source_checksum` of an import.
std::string file_checksum(const std::string& path);

/// The packing fraction of N/2 small (d = 1) and N/2 big (d = ratio) particles in a box of
/// side L in D dimensions.
double packing_fraction_of(int dim, std::int64_t n, double diameter_ratio, double box_length);

}  // namespace jam
