#pragma once
// Hostile HDF5 files for the tests and fuzz targets of the readers: valid templates written by
// jam's own writers (a run file, a checkpoint, a start, a stats.h5), and edits made with the
// HDF5 C API that a damaged or forged file could carry (an attribute turned into an array or
// another class, a dataset of another length or class, a declared but unwritten dataset, a link
// that makes a group contain itself, a flipped bit in a dimension).
#include <hdf5.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/io/chain_start.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/run_file.hpp"
#include "sim/run/compression_run.hpp"

namespace jam::test {

inline std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// The HDF5 classes an edit can give an attribute or dataset.
enum class ValueClass { kInteger, kFloat, kString, kVariableString, kCompound };

/// An HDF5 file opened for writing with the C API, for edits jam's own writer never makes.
/// Holds the library lock like h5::File, so that edits never run beside jam's readers.
class Editor {
 public:
  explicit Editor(const std::filesystem::path& path)
      : lock_(h5::library_mutex()), id_(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) {
    if (id_ < 0) throw std::runtime_error("cannot open " + path.string() + " for editing");
  }
  Editor(const Editor&) = delete;
  Editor& operator=(const Editor&) = delete;
  ~Editor() { H5Fclose(id_); }
  hid_t id() const { return id_; }

  /// Replaces attribute `name` of `object` by one of class `cls` and extent `dims` ({}:
  /// scalar), its values made from `bytes` (repeated; zeros when empty).
  void set_attribute(const std::string& object, const std::string& name, ValueClass cls,
                     const std::vector<hsize_t>& dims, const std::string& bytes = "\1") {
    if (H5Aexists_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
      H5Adelete_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT);
    }
    const Owned space = make_space(dims);
    const Owned type = make_type(cls);
    const hid_t attr = H5Acreate_by_name(id_, object.c_str(), name.c_str(), type.id, space.id,
                                         H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (attr < 0) throw std::runtime_error("cannot create attribute " + name);
    const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id));
    const std::vector<char> values = fill(cls, n, type.id, bytes);
    std::vector<const char*> texts(n, "forged");
    H5Awrite(attr, type.id,
             cls == ValueClass::kVariableString ? static_cast<const void*>(texts.data())
                                                : values.data());
    H5Aclose(attr);
  }

  /// Replaces attribute `name` of `object` by a scalar variable-length string holding `text`
  /// (as jam writes its text attributes).
  void set_text(const std::string& object, const std::string& name, const std::string& text) {
    set_attribute(object, name, ValueClass::kVariableString, {});
    const hid_t attr = H5Aopen_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    const Owned type = make_type(ValueClass::kVariableString);
    const char* value = text.c_str();
    H5Awrite(attr, type.id, &value);
    H5Aclose(attr);
  }

  void set_int(const std::string& name, std::int64_t value) {
    std::string bytes(sizeof value, '\0');
    std::memcpy(bytes.data(), &value, sizeof value);
    set_attribute(".", name, ValueClass::kInteger, {}, bytes);
  }

  void set_double(const std::string& name, double value) {
    std::string bytes(sizeof value, '\0');
    std::memcpy(bytes.data(), &value, sizeof value);
    set_attribute(".", name, ValueClass::kFloat, {}, bytes);
  }

  /// Replaces dataset `name` by one of class `cls` and extent `dims`, written from `bytes`.
  void set_dataset(const std::string& name, ValueClass cls, const std::vector<hsize_t>& dims,
                   const std::string& bytes = "") {
    if (H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0) H5Ldelete(id_, name.c_str(), H5P_DEFAULT);
    const Owned space = make_space(dims);
    const Owned type = make_type(cls);
    const hid_t set =
        H5Dcreate2(id_, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (set < 0) throw std::runtime_error("cannot create dataset " + name);
    const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id));
    if (cls != ValueClass::kVariableString) {
      const std::vector<char> values = fill(cls, n, type.id, bytes);
      H5Dwrite(set, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    }
    H5Dclose(set);
  }

  void set_doubles(const std::string& name, const std::vector<double>& values) {
    std::string bytes(values.size() * sizeof(double), '\0');
    std::memcpy(bytes.data(), values.data(), bytes.size());
    set_dataset(name, ValueClass::kFloat, {values.size()}, bytes);
  }

  /// A chunked dataset of `n` doubles of which no chunk was ever written: HDF5 makes its values
  /// up from the fill value, however many are asked for.
  void add_unwritten(const std::string& name, hsize_t n) {
    if (H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0) H5Ldelete(id_, name.c_str(), H5P_DEFAULT);
    const Owned space{H5Screate_simple(1, &n, nullptr), H5Sclose};
    const Owned dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    const hsize_t chunk = 1024;
    H5Pset_chunk(dcpl.id, 1, &chunk);
    H5Dclose(
        H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT));
  }

  /// A dataset of `n` doubles whose values are stored in the file `elsewhere` (external
  /// storage), never written: creating it opens nothing, reading it would open `elsewhere`.
  void add_external(const std::string& name, hsize_t n, const std::string& elsewhere) {
    if (H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0) H5Ldelete(id_, name.c_str(), H5P_DEFAULT);
    const Owned space{H5Screate_simple(1, &n, nullptr), H5Sclose};
    const Owned dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    H5Pset_external(dcpl.id, elsewhere.c_str(), 0, n * sizeof(double));
    const hid_t set =
        H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT);
    if (set < 0) throw std::runtime_error("cannot create dataset " + name);
    H5Dclose(set);
  }

  /// A chunked dataset of `written` doubles, then extended to `n`: the chunks past the first
  /// were never written, as when a flipped bit raises a dimension.
  void add_extended(const std::string& name, hsize_t written, hsize_t n) {
    if (H5Lexists(id_, name.c_str(), H5P_DEFAULT) > 0) H5Ldelete(id_, name.c_str(), H5P_DEFAULT);
    const hsize_t unlimited = H5S_UNLIMITED;
    const Owned space{H5Screate_simple(1, &written, &unlimited), H5Sclose};
    const Owned dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    const hsize_t chunk = 64;
    H5Pset_chunk(dcpl.id, 1, &chunk);
    const Owned set{
        H5Dcreate2(id_, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT),
        H5Dclose};
    if (set.id < 0) throw std::runtime_error("cannot create dataset " + name);
    const std::vector<double> values(written, 0.5);
    H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dset_extent(set.id, &n);
  }

  /// Removes attribute `name` of `object`, or the link `name` when object is "".
  void remove(const std::string& object, const std::string& name) {
    if (object.empty()) {
      H5Ldelete(id_, name.c_str(), H5P_DEFAULT);
    } else {
      H5Adelete_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT);
    }
  }

  /// A hard link `name` to the group `target`: a group inside itself when target is above it.
  void link(const std::string& target, const std::string& name) {
    if (H5Lcreate_hard(id_, target.c_str(), id_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0) {
      throw std::runtime_error("cannot link " + name);
    }
  }

 private:
  struct Owned {
    hid_t id;
    herr_t (*close)(hid_t);
    ~Owned() { close(id); }
  };

  static Owned make_space(const std::vector<hsize_t>& dims) {
    return {dims.empty() ? H5Screate(H5S_SCALAR)
                         : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
            H5Sclose};
  }

  static Owned make_type(ValueClass cls) {
    switch (cls) {
      case ValueClass::kInteger:
        return {H5Tcopy(H5T_STD_I64LE), H5Tclose};
      case ValueClass::kFloat:
        return {H5Tcopy(H5T_IEEE_F64LE), H5Tclose};
      case ValueClass::kString: {
        const hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, 16);
        return {t, H5Tclose};
      }
      case ValueClass::kVariableString: {
        const hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, H5T_VARIABLE);
        return {t, H5Tclose};
      }
      case ValueClass::kCompound: {
        const hid_t t = H5Tcreate(H5T_COMPOUND, 16);
        H5Tinsert(t, "a", 0, H5T_NATIVE_INT64);
        H5Tinsert(t, "b", 8, H5T_NATIVE_DOUBLE);
        return {t, H5Tclose};
      }
    }
    return {H5Tcopy(H5T_STD_I64LE), H5Tclose};
  }

  /// n values of `type`, their bytes repeated from `bytes` (1 as the value when empty).
  static std::vector<char> fill(ValueClass cls, std::size_t n, hid_t type,
                                const std::string& bytes) {
    const std::size_t size = cls == ValueClass::kVariableString ? 0 : H5Tget_size(type);
    std::vector<char> v(n * size, '\0');
    if (bytes.empty()) {
      for (std::size_t k = 0; k < n; ++k) {
        if (cls == ValueClass::kFloat) {
          const double one = 1.0;
          std::memcpy(v.data() + k * size, &one, sizeof one);
        } else if (size > 0) {
          v[k * size] = cls == ValueClass::kString ? 'x' : 1;
        }
      }
      return v;
    }
    for (std::size_t k = 0; k < v.size(); ++k) v[k] = bytes[k % bytes.size()];
    return v;
  }

  std::unique_lock<std::mutex> lock_;
  hid_t id_;
};

/// Raises dimension 0 of dataset `name` from `length` to length + 2^bit by flipping one bit
/// of the file's bytes, as damage would: each 8-byte occurrence of `length` is tried and kept
/// when HDF5 then reads the new extent. False when none is the dimension.
inline bool flip_dimension(const std::filesystem::path& file, const std::string& name,
                           std::uint64_t length, int bit) {
  const std::string original = file_bytes(file);
  char pattern[sizeof length];
  std::memcpy(pattern, &length, sizeof length);
  const std::uint64_t wanted = length ^ (std::uint64_t{1} << bit);
  for (auto at = original.find(std::string(pattern, sizeof length)); at != std::string::npos;
       at = original.find(std::string(pattern, sizeof length), at + 1)) {
    std::string bytes = original;
    bytes[at + static_cast<std::size_t>(bit / 8)] ^= static_cast<char>(1 << (bit % 8));
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    hsize_t dims[H5S_MAX_RANK] = {};
    {
      std::unique_lock lock(h5::library_mutex());
      const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      const hid_t set = f < 0 ? -1 : H5Dopen2(f, name.c_str(), H5P_DEFAULT);
      const hid_t space = set < 0 ? -1 : H5Dget_space(set);
      if (space >= 0) H5Sget_simple_extent_dims(space, dims, nullptr);
      if (space >= 0) H5Sclose(space);
      if (set >= 0) H5Dclose(set);
      if (f >= 0) H5Fclose(f);
    }
    if (dims[0] == wanted) return true;
  }
  std::ofstream(file, std::ios::binary | std::ios::trunc) << original;
  return false;
}

/// A sound run file DIR/NAME of N = 64, 2D, 0.70 -> 0.72 (5 output points), written by jam in
/// a fraction of a second: the file a case plants its fault in.
inline std::filesystem::path valid_run_file(const std::filesystem::path& dir,
                                            const std::string& name) {
  SimConfig c;
  c.n = 64;
  c.phi_init = 0.7;
  c.phi_stop = 0.72;
  c.phi_step = 0.005;
  c.compression_rate = 1e-2;
  c.seed = 3;
  c.quiet = true;
  c.checkpoint_interval = 0;
  c.out = (dir / name).string();
  run_compression(c);
  if (const std::string why = run_file_problem(c.out); !why.empty())
    throw std::runtime_error("the template run file is not sound: " + why);
  return c.out;
}

/// A checkpoint of N = 8 particles in 2D with `points` output points and two kept
/// configurations, written by jam's writer (sealed).
inline void write_template_checkpoint(const std::string& path, const std::string& fingerprint,
                                      std::size_t points = 3) {
  constexpr std::size_t n = 8;
  ParticleData<2> p;
  p.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.id[i] = static_cast<std::uint32_t>(i);
    p.type[i] = static_cast<std::uint8_t>(i % 2);
    p.s[0][i] = (static_cast<double>(i) + 0.5) / n;
    p.s[1][i] = 0.25;
  }
  RunState<2> st;
  st.phase = RunState<2>::kCompressing;
  st.steps = 100;
  st.next_output = static_cast<std::int64_t>(points);
  for (std::size_t k = 0; k < points; ++k) {
    Observables<2> o{};
    o.packing_fraction = 0.7 + 0.01 * static_cast<double>(k);
    o.time = static_cast<double>(k);
    st.points.push_back(o);
  }
  // A jamming-point search under way: the first configuration released, three kept.
  st.saved.push_back({0.70, {}});
  for (int k = 1; k < 4; ++k) st.saved.push_back({0.7 + 0.01 * k, std::vector<double>(2 * n, 0.5)});
  st.jamming_answers = {0, 1, 1};
  st.cpu_seconds = 12.5;
  const StepperState stepper = {{"velocity_0", std::vector<double>(n, 0.0)},
                                {"velocity_1", std::vector<double>(n, 0.0)},
                                {"have_forces", {1.0}}};
  write_checkpoint<2>(path, fingerprint, st, p, stepper);
}

/// A chained start of N = 8 particles in 2D, written by jam's writer (sealed).
inline void write_template_start(const std::string& path, const std::string& identity) {
  ChainStart<2> s;
  s.particles.resize(8);
  for (std::size_t i = 0; i < 8; ++i) {
    s.particles.id[i] = static_cast<std::uint32_t>(i);
    s.particles.type[i] = static_cast<std::uint8_t>(i % 2);
    s.particles.s[0][i] = (static_cast<double>(i) + 0.5) / 8;
    s.particles.s[1][i] = 0.5;
  }
  s.box_length = 10.0;
  s.packing_fraction = 0.7;
  s.identity = identity;
  write_chain_start<2>(path, s);
}

/// A stats.h5 with one ensemble of `samples` samples on a grid of `points` packings: what
/// `jam check` and `jam stats --refit` read, written with jam's writer.
inline void write_template_stats(const std::string& path, std::size_t samples = 4,
                                 std::size_t points = 5) {
  // What reference/schema/stats.toml requires of a stats.h5, and little more.
  h5::File f = h5::File::create(path);
  f.write_attribute("campaign", std::string("template"));
  f.write_attribute("dim", std::int64_t{2});
  f.write_attribute("version", std::string("template"));
  f.write_attribute("pooled_sizes", std::int64_t{0});
  f.write_attribute("runs", static_cast<std::int64_t>(samples));
  f.write_attribute("runs_skipped", std::int64_t{0});
  const std::string g = "ensembles/n64_phi0.7000_r-2.00";
  f.create_group(g + "/constant_phi");
  f.write_attribute("n", std::int64_t{64}, g);
  f.write_attribute("phi_init", 0.7, g);
  f.write_attribute("log10_rate", -2.0, g);
  f.write_attribute("compression_rate", 0.01, g);
  f.write_attribute("samples", static_cast<std::int64_t>(samples), g);
  std::vector<double> grid, ids, pressure, mean;
  for (std::size_t k = 0; k < points; ++k) grid.push_back(0.80 + 0.001 * static_cast<double>(k));
  for (std::size_t k = 0; k < points; ++k) mean.push_back(1e-3 * static_cast<double>(k + 1));
  for (std::size_t s = 0; s < samples; ++s) {
    ids.push_back(static_cast<double>(s));
    pressure.insert(pressure.end(), mean.begin(), mean.end());
  }
  f.write_dataset(g + "/constant_phi/packing_fraction", grid);
  f.write_dataset(g + "/constant_phi/sample_ids", ids);
  f.write_dataset(g + "/constant_phi/pressure_mean", mean);
  f.write_dataset(g + "/constant_phi/pressure_samples", pressure, {samples, points});
  f.write_dataset(g + "/constant_phi/contacts_per_particle_samples", pressure, {samples, points});
  // Constant Z on its own grid and samples, the jamming points, the fit's window.
  f.create_group(g + "/constant_z");
  f.write_dataset(g + "/constant_z/contacts_per_particle", grid);
  f.write_dataset(g + "/constant_z/sample_ids", ids);
  f.write_dataset(g + "/constant_z/pressure_mean", mean);
  f.write_dataset(g + "/constant_z/pressure_samples", pressure, {samples, points});
  f.create_group(g + "/jamming");
  f.write_dataset(g + "/jamming/packing_fraction_samples", std::vector<double>(samples, 0.84));
  f.write_dataset(g + "/jamming/sample_ids", ids);
  const std::string fit = "fit/representative";
  f.create_group(fit);
  f.write_attribute("phi_min", 0.8, fit);
  f.write_attribute("phi_j", 0.84, fit);
  for (const char* name : {"phi_j_error", "beta", "beta_error", "y", "y_error"})
    f.write_attribute(name, 0.1, fit);
  f.write_attribute("samples", static_cast<std::int64_t>(samples), fit);
  f.close();
}

}  // namespace jam::test
