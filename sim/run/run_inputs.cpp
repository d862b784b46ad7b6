#include "sim/run/run_inputs.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"

namespace jam {

std::string checked_writable(const std::string& option, const std::string& path) {
  const std::string target = checked_output_file(option, path);
  // The longest name written beside it: "<name>.checkpoint.<pid>-<tid>.partial" (pid and tid
  // of at most 10 digits). A name the file system cannot hold would otherwise fail only at the
  // first checkpoint, after the work.
  constexpr std::size_t kLongestSuffix = sizeof(".checkpoint.4294967295-4294967295.partial") - 1;
  const std::filesystem::path p(target);
  const std::string directory = p.has_parent_path() ? p.parent_path().string() : ".";
  const long name_max = ::pathconf(directory.c_str(), _PC_NAME_MAX);
  const std::size_t length = p.filename().string().size();
  if (name_max > 0 && length + kLongestSuffix > static_cast<std::size_t>(name_max)) {
    throw ConfigError(fmt::format(
        "--{} {}: a file name of {} characters is too long (at most {} here, leaving room for "
        "the names of its checkpoint and temporaries)",
        option, path, length, static_cast<std::size_t>(name_max) - kLongestSuffix));
  }
  const std::string probe = AtomicFile::temporary_name(target);
  std::FILE* f = std::fopen(probe.c_str(), "w");
  if (!f) {
    throw ConfigError(
        fmt::format("--{} {}: cannot write there: {}", option, path, std::strerror(errno)));
  }
  std::fclose(f);
  std::remove(probe.c_str());
  return target;
}

}  // namespace jam
