#pragma once
// A test executable's scratch directory: one per process, jam-<suite>-<pid> under the system's
// temporary directory, made when the executable starts and removed with everything in it when
// it ends (its runs, logs and campaign files; a failed test leaves nothing behind, and two
// suites run in parallel by ctest never share one).
//
//   const jam::test::ScratchDir kDir("pipeline");
//   ... kDir / "campaign.toml", (kDir / "runs").string(), fs::exists(kDir) ...
#include <unistd.h>

#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

namespace jam::test {

class ScratchDir {
 public:
  explicit ScratchDir(std::string_view suite)
      : path_(std::filesystem::temp_directory_path() /
              ("jam-" + std::string(suite) + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);  // a directory an earlier process of this pid left
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;  // nothing to report to once the tests have ended
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  operator const std::filesystem::path&() const { return path_; }  // NOLINT: used as a path
  std::filesystem::path operator/(const std::filesystem::path& p) const { return path_ / p; }
  std::string string() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace jam::test
