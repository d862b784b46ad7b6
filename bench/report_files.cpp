#include "bench/report_files.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>

#include "sim/io/atomic_file.hpp"
#include "sim/io/install_paths.hpp"
#include "sim/io/process.hpp"

namespace jam::bench {

std::string machine_description() {
  std::ifstream in("/proc/cpuinfo");
  std::string model = "unknown CPU";
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  return fmt::format("{}, {} cores", model, std::thread::hardware_concurrency());
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

void write_text_file(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  std::fputs(text.c_str(), f.stream());
  f.commit();
}

bool plot(const std::string& kind, const std::string& csv, const std::string& png) {
  const std::string script = data_path("bench/plot_benchmarks.py").string();
  int status = 127;
  try {
    status = run_program({"/usr/bin/python3", script, kind, csv, png});
  } catch (const std::exception&) {
  }
  if (status != 0) {
    fmt::print(stderr, "jam bench: no plot {} ({} failed; needs python3-matplotlib)\n", png,
               script);
    return false;
  }
  return true;
}

}  // namespace jam::bench
