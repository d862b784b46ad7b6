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

#include "sim/io/open_run_schema.hpp"

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
  double quality_factor = 0.0;  // Q, inertial only (attribute "q")
  double compression_rate = 0.0, phi_init = 0.0;
  std::string simulator, simulator_version;
  std::int64_t sample = 0;
  std::optional<double> jamming_packing_fraction;
  std::string source, source_checksum, interpolation;  // provenance, may be empty
  bool jam_native = false;                             // a run file of jam's own (read only)
  // One entry per output point (empty: not stored).
  std::vector<double> packing_fraction, pressure, contacts_per_particle, energy_per_particle, time;
};

/// Each series of the format (a dataset, one value per output point), the unit its `units`
/// attribute must state, and whether it must be there.
struct OpenRunSeries {
  const char* name;
  const char* unit;
  bool required;
  std::vector<double> OpenRun::*values;
};
inline const OpenRunSeries kOpenRunSeries[] = {
    {"packing_fraction", "1", true, &OpenRun::packing_fraction},
    {"pressure", "k_e/d_s^D", true, &OpenRun::pressure},
    {"contacts_per_particle", "1", false, &OpenRun::contacts_per_particle},
    {"energy_per_particle", "k_e", false, &OpenRun::energy_per_particle},
    {"time", "t0", false, &OpenRun::time},
};

/// Checks r against the spec; throws std::runtime_error "<where>: <field> <value> ...".
/// The contact laws allowed are the schema's (by default the binary's registry, ContactLaws).
void validate_open_run(const OpenRun& r, const std::string& where,
                       const OpenRunSchema& schema = open_run_schema());

/// The model's part of it alone (dim, n, diameter_ratio, contact, dynamics, q), for records
/// that hold a run's model without its series (external.toml) and for frames files.
void validate_open_run_model(const OpenRun& r, const std::string& where,
                             const OpenRunSchema& schema = open_run_schema());

/// Reads and checks an open run, or a run file of jam's own (recognised by its `checksum`,
/// which is verified; simulator "jam"). Throws std::runtime_error naming file and field.
OpenRun read_open_run(const std::string& path, const OpenRunSchema& schema = open_run_schema());

/// Checks r, then writes it to path through a temporary renamed when complete (the path must
/// be a regular file or absent: output_path.hpp). Nothing is left behind on error.
void write_open_run(const std::string& path, const OpenRun& r,
                    const OpenRunSchema& schema = open_run_schema());

/// FNV-1a (64 bit) of a file's bytes as 16 hex digits: the `source_checksum` of an import.
std::string file_checksum(const std::string& path);

/// The packing fraction of N/2 small (d = 1) and N/2 big (d = ratio) particles in a box of
/// side L in D dimensions.
double packing_fraction_of(int dim, std::int64_t n, double diameter_ratio, double box_length);

}  // namespace jam
