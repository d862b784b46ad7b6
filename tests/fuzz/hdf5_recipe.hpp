#pragma once
// Structured fuzzing of the HDF5 readers: the fuzz input is a recipe of edits to a valid file
// written by jam (tests/hostile_hdf5.hpp), not the file's bytes, so that what varies is what
// a reader must check before it reads: which attribute or dataset, its class, its rank and
// extent, its values; a dataset declared far larger than it was written; a link that makes a
// group contain itself. Mutating bytes alone mostly breaks the seal or HDF5's own parsing and
// never reaches these checks.
//
// Recipe: byte 0 holds flags (bit 0: forge the checksum or seal after the edits, so that the
// reader's own checks are all that stands between the edits and the values), then up to
// kMaxEdits edits of 8 bytes plus their value bytes:
//   op, target (an index into the reader's names), class, rank, three dimension bytes, and the
//   number of value bytes that follow (at most 31).
// Written arrays have at most 64 x 64 values, so a recipe never makes the fuzzer itself
// allocate much; declared-only extents (unwritten, extended) go up to 2^47 values.
#include <hdf5.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../hostile_hdf5.hpp"

namespace jam::fuzz {

/// An attribute `name` of `object` ("." the root group), or a dataset (`object` empty: `name`
/// is its path).
struct Target {
  std::string object;
  std::string name;
};

enum class Op : std::uint8_t {
  kAttribute,  // replace an attribute: class, rank, extent and value bytes from the recipe
  kDataset,    // replace a dataset likewise
  kUnwritten,  // a chunked dataset declared with a huge extent, no chunk written
  kExtended,   // a chunked dataset written short, then its extent raised far beyond
  kLoop,       // a hard link to the root group inside the target's group
  kDelete,     // remove the target
  kCount
};

constexpr std::size_t kMaxEdits = 8;
constexpr std::size_t kEditBytes = 8;

class Recipe {
 public:
  Recipe(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool forge() const { return size_ > 0 && (data_[0] & 1) != 0; }

  /// Applies the edits to the file at `path`; targets are indexes into `targets`.
  void apply(const std::filesystem::path& path, const std::vector<Target>& targets) const {
    test::Editor e(path);
    std::size_t at = 1;
    for (std::size_t k = 0; k < kMaxEdits && at + kEditBytes <= size_; ++k) {
      const std::uint8_t* edit = data_ + at;
      const std::size_t value_size = std::min<std::size_t>(edit[7] % 32, size_ - at - kEditBytes);
      const std::string value(reinterpret_cast<const char*>(edit + kEditBytes), value_size);
      at += kEditBytes + value_size;
      apply_one(e, edit, targets[edit[1] % targets.size()], value);
    }
  }

 private:
  static void apply_one(test::Editor& e, const std::uint8_t* edit, const Target& t,
                        const std::string& value) {
    const auto op = static_cast<Op>(edit[0] % static_cast<int>(Op::kCount));
    const auto cls = static_cast<test::ValueClass>(edit[2] % 5);
    std::vector<hsize_t> dims;
    for (int d = 0; d < edit[3] % 3; ++d) dims.push_back(edit[4 + d] % 65);
    const hsize_t huge = hsize_t{1} << (edit[4] % 48);
    const std::string path = t.object.empty() ? t.name : t.object + "/" + t.name;
    const std::string group = t.object.empty() || t.object == "." ? "" : t.object;
    switch (op) {
      case Op::kAttribute:  // on a dataset: its "units", as run files carry
        if (t.object.empty()) e.set_attribute(t.name, "units", cls, dims, value);
        if (!t.object.empty()) e.set_attribute(t.object, t.name, cls, dims, value);
        break;
      case Op::kDataset:
        e.set_dataset(path, cls, dims.empty() ? std::vector<hsize_t>{1} : dims, value);
        break;
      case Op::kUnwritten:
        e.add_unwritten(path, huge);
        break;
      case Op::kExtended:
        e.add_extended(path, edit[5] % 65, huge);
        break;
      case Op::kLoop:
        e.link("/", group + "/loop");
        break;
      case Op::kDelete:
        e.remove(t.object, t.name);
        break;
      case Op::kCount:
        break;
    }
  }

  const std::uint8_t* data_;
  std::size_t size_;
};

/// A scratch file of this process, a copy of `template_bytes`, edited by `recipe`; edits that
/// HDF5 itself refuses (a name that cannot be created) are skipped by the Editor's callers.
inline std::filesystem::path prepare(const std::string& stem, const std::string& template_bytes,
                                     const Recipe& recipe, const std::vector<Target>& targets) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / (stem + "-" + std::to_string(::getpid()) + ".h5");
  std::ofstream(path, std::ios::binary | std::ios::trunc) << template_bytes;
  try {
    recipe.apply(path, targets);
  } catch (const std::exception&) {
    // An edit HDF5 refused: the file holds the edits made before it.
  }
  return path;
}

}  // namespace jam::fuzz
