#include "sim/io/output_path.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "sim/run/sim_config.hpp"

namespace jam {
namespace fs = std::filesystem;
namespace {

const char* kind(fs::file_type t) {
  switch (t) {
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::regular:
      return "a regular file";
    default:
      return "not a regular file";
  }
}

[[noreturn]] void refuse(const std::string& option, const std::string& path,
                         const std::string& why) {
  throw ConfigError(fmt::format("--{} {}: {}", option, path, why));
}

}  // namespace

std::string output_file_target(const std::string& path) {
  auto refuse_path = [&path](const std::string& why) {
    throw OutputPathError(fmt::format("{}: {}", path.empty() ? "''" : path, why));
  };
  if (path.empty()) refuse_path("an output file name is required");
  if (path.back() == '/') refuse_path("names a directory, not a file");
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (link.type() == fs::file_type::not_found) return path;
  const fs::file_status target = fs::status(path, ec);
  const bool is_link = link.type() == fs::file_type::symlink;
  if (is_link && target.type() == fs::file_type::not_found) {
    refuse_path("is a symbolic link to a missing file; give the file's own path");
  }
  if (target.type() != fs::file_type::regular) {
    refuse_path(fmt::format("is {}{}; only a regular file (or a new name) can be replaced",
                            kind(target.type()), is_link ? " (through a symbolic link)" : ""));
  }
  return is_link ? fs::canonical(path).string() : path;
}

std::string checked_output_file(const std::string& option, const std::string& path) {
  try {
    return output_file_target(path);
  } catch (const OutputPathError& e) {
    throw ConfigError(fmt::format("--{} {}", option, e.what()));
  }
}

void check_output_directory(const std::string& option, const std::string& path) {
  if (path.empty()) refuse(option, "''", "an output directory is required");
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (link.type() == fs::file_type::not_found) return;
  const fs::file_status target = fs::status(path, ec);
  if (link.type() == fs::file_type::symlink && target.type() == fs::file_type::not_found) {
    refuse(option, path, "is a symbolic link to a missing directory");
  }
  if (target.type() != fs::file_type::directory) {
    refuse(option, path, fmt::format("is {}, not a directory", kind(target.type())));
  }
}

void check_input_file(const std::string& what, const std::string& path) {
  std::error_code ec;
  const fs::file_status target = fs::status(path, ec);
  if (target.type() == fs::file_type::not_found || target.type() == fs::file_type::regular) return;
  if (ec && target.type() == fs::file_type::none) {
    throw std::runtime_error(fmt::format("{} {}: cannot read: {}", what, path, ec.message()));
  }
  throw std::runtime_error(fmt::format("{} {}: is {}; only a regular file can be read", what, path,
                                       kind(target.type())));
}

}  // namespace jam
