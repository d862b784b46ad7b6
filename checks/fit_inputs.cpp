#include "checks/fit_inputs.hpp"

#include <cmath>
#include <filesystem>

#include "checks/verdict_file.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/open_run.hpp"

namespace jam::checks {
namespace {

/// values[key] when the verdict has a finite one.
std::optional<double> value(const Verdict& v, const char* key) {
  const auto it = v.values.find(key);
  if (it == v.values.end() || !std::isfinite(it->second)) return std::nullopt;
  return it->second;
}

}  // namespace

stats::FitVerdicts fit_verdicts(const std::string& directory) {
  namespace fs = std::filesystem;
  stats::FitVerdicts out;
  std::string checksums;
  for (const char* name : {"checks.json", "checks-phi_init.json"}) {
    const fs::path path = fs::path(directory) / name;
    if (!fs::exists(fs::symlink_status(path))) continue;
    const VerdictFile file = read_verdict_file(path.string());
    out.files += (out.files.empty() ? "" : ", ") + std::string(name);
    checksums += file_checksum(path.string()) + "\n";
    const bool all = std::string(name) == "checks.json";
    out.checks_json = out.checks_json || all;
    for (const Verdict& v : file.verdicts) {
      const auto phi = value(v, "phi_init"), rate = value(v, "log10_rate");
      if (!phi || !rate) continue;
      const bool pass = v.status == "pass";
      if (v.check == "phi_init") {
        if (const auto n = value(v, "n"))
          out.phi_init.push_back(
              {static_cast<std::int64_t>(std::llround(*n)), *phi, *rate, pass, name});
      } else if (all && v.check == "finite_size" && (v.region.empty() || v.region == "pooled") &&
                 value(v, "constant_z").value_or(0.0) == 0.0) {
        out.finite_size.push_back({0, *phi, *rate, pass, name});
      }
    }
  }
  if (!checksums.empty()) out.files_checksum = checksum_text(bytes_checksum(checksums));
  return out;
}

}  // namespace jam::checks
