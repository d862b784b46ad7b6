#include "sim/io/chain_start.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "sim/io/atomic_file.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/fnv1a.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/particle_datasets.hpp"
#include "sim/io/sealed_file.hpp"

namespace jam {
namespace {

/// Opens a sealed start, checking the seal before HDF5 parses anything.
h5::File open_sealed(const std::string& path) {
  if (!std::filesystem::exists(path)) throw CorruptCheckpoint(path + ": no such chained start");
  if (const std::string why = sealed_file_problem(path); !why.empty()) throw CorruptCheckpoint(why);
  try {
    return h5::File::open_read(path);
  } catch (const std::exception& e) {
    throw CorruptCheckpoint(e.what());
  }
}

}  // namespace

std::string chain_start_identity(const std::string& parent_fingerprint, double packing) {
  return fmt::format("{} at packing {:.17g}", parent_fingerprint, packing);
}

std::string chain_start_key(const std::string& identity) {
  Fnv1a h;
  h.add(identity);
  return h.hex();
}

template <int D>
void write_chain_start(const std::string& path, const ChainStart<D>& start) {
  write_sealed(path, [&](h5::File& f) {
    f.write_attribute("identity", start.identity);
    f.write_attribute("box_length", start.box_length);
    f.write_attribute("packing_fraction", start.packing_fraction);
    f.write_attribute("dim", std::int64_t{D});
    write_particles(f, start.particles);
  });
}

std::string stored_chain_start_identity(const std::string& path) {
  const h5::File f = open_sealed(path);
  try {
    return f.read_attribute_string("identity");
  } catch (const std::exception& e) {
    throw CorruptCheckpoint(e.what());
  }
}

template <int D>
ChainStart<D> read_chain_start(const std::string& path, const std::string& identity) {
  const h5::File f = open_sealed(path);  // the seal once, before anything is read
  ChainStart<D> s;
  try {
    s.identity = f.read_attribute_string("identity");
  } catch (const std::exception& e) {
    throw CorruptCheckpoint(e.what());
  }
  if (!identity.empty() && s.identity != identity) {
    throw ForeignCheckpoint(
        fmt::format("chained start '{}' was taken from another run or packing", path));
  }
  try {
    if (const auto dim = f.read_attribute_int("dim"); dim != D) {
      throw std::runtime_error(fmt::format("{}: attribute 'dim' = {}, expected {}", path, dim, D));
    }
    s.box_length = f.read_attribute_double("box_length");
    s.packing_fraction = f.read_attribute_double("packing_fraction");
    if (!(s.box_length > 0.0 && std::isfinite(s.box_length))) {
      throw std::runtime_error(fmt::format(
          "{}: attribute 'box_length' = {} is not positive and finite", path, s.box_length));
    }
    if (!(s.packing_fraction > 0.0 && s.packing_fraction < 1.0)) {
      throw std::runtime_error(fmt::format(
          "{}: attribute 'packing_fraction' = {} is outside (0, 1)", path, s.packing_fraction));
    }
    s.particles = read_particles<D>(f, path);
    return s;
  } catch (const std::exception& e) {
    throw CorruptCheckpoint(e.what());
  }
}

std::string chain_start_problem(const std::string& path, const std::string& identity) {
  try {
    if (stored_chain_start_identity(path) != identity) return "taken from another run or packing";
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

template void write_chain_start<2>(const std::string&, const ChainStart<2>&);
template void write_chain_start<3>(const std::string&, const ChainStart<3>&);
template ChainStart<2> read_chain_start<2>(const std::string&, const std::string&);
template ChainStart<3> read_chain_start<3>(const std::string&, const std::string&);

}  // namespace jam
