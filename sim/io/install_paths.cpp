#include "sim/io/install_paths.hpp"

#ifndef JAM_SOURCE_TREE
#define JAM_SOURCE_TREE "."
#endif

namespace jam {

std::filesystem::path executable_directory() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path(".") : exe.parent_path();
}

std::filesystem::path data_path(const std::string& relative) {
  const std::filesystem::path installed =
      executable_directory().parent_path() / "share" / "jam" / relative;
  std::error_code ec;
  if (std::filesystem::exists(installed, ec)) return installed;
  return std::filesystem::path(JAM_SOURCE_TREE) / relative;
}

}  // namespace jam
