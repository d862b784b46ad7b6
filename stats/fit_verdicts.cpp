#include "stats/fit_verdicts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/io/content_checksum.hpp"
#include "sim/io/hdf5_file.hpp"
#include "stats/campaign_stats.hpp"

namespace jam::stats {
namespace {

bool same_phi(double a, double b) {
  return std::abs(a - b) <= 1e-9;
}

}  // namespace

std::string FitVerdicts::checksum() const {
  if (empty() && !checks_json) return "none";
  std::string bytes = checks_json ? "checks.json\n" : "\n";
  for (const auto* list : {&phi_init, &finite_size}) {
    for (const Judged& j : *list)
      bytes += fmt::format("{} {:.17g} {:.17g} {} {}\n", j.n, j.phi_init, j.log10_rate,
                           j.pass ? "pass" : "not", j.file);
    bytes += "--\n";
  }
  return checksum_text(bytes_checksum(bytes));
}

FitSelection fit_selection(const std::vector<EnsembleKey>& ensembles, double fit_phi_init,
                           std::int64_t fit_size) {
  FitSelection s;
  if (ensembles.empty()) return s;
  s.fitted = true;
  s.n = fit_size;
  s.phi_init = fit_phi_init;
  s.lowest_phi_init = ensembles.front().phi_init;
  for (const EnsembleKey& k : ensembles) {
    s.lowest_phi_init = std::min(s.lowest_phi_init, k.phi_init);
    // The paper's protocol (papers_protocol.cpp): fit_phi_init, rates at most 10^-6.5.
    if (same_phi(k.phi_init, fit_phi_init) && k.n != 0 &&
        k.log10_rate <= kPapersLog10RateMax + 1e-9) {
      s.papers_sizes.insert(k.n);
      s.papers_rates.insert(k.log10_rate);
    }
  }
  return s;
}

FitVerdicts consulted(const FitVerdicts& all, const FitSelection& s) {
  FitVerdicts out;
  if (!s.fitted) return out;
  std::set<std::string> files;
  if (!same_phi(s.phi_init, s.lowest_phi_init)) {
    for (const auto& v : all.phi_init)
      if (v.n == s.n && same_phi(v.phi_init, s.phi_init))
        out.phi_init.push_back(v), files.insert(v.file);
  }
  if (s.papers_sizes.size() >= 2) {
    out.checks_json = all.checks_json;
    for (const auto& v : all.finite_size)
      if (same_phi(v.phi_init, s.phi_init)) out.finite_size.push_back(v), files.insert(v.file);
    if (all.checks_json) files.insert("checks.json");
  }
  for (const auto& f : files) out.files += (out.files.empty() ? "" : ", ") + f;
  if (!out.files.empty()) out.files_checksum = all.files_checksum;
  return out;
}

std::string fit_verdicts_change(const std::string& directory, const FitVerdicts& now) {
  const std::string path = (std::filesystem::path(directory) / "stats.h5").string();
  std::string recorded;
  FitSelection s;
  try {
    const h5::File f = h5::File::open_read(path);
    if (!f.has_attribute("fit_verdicts_checksum")) return "";
    recorded = f.read_attribute_string("fit_verdicts_checksum");
    std::vector<EnsembleKey> keys;
    for (const auto& name : f.list_group("ensembles")) {
      const std::string g = "ensembles/" + name;
      keys.push_back({f.read_attribute_int("n", g), f.read_attribute_double("phi_init", g),
                      f.read_attribute_double("log10_rate", g)});
    }
    if (f.has_attribute("fit_verdicts_phi_init"))
      s = fit_selection(keys, f.read_attribute_double("fit_verdicts_phi_init"),
                        f.read_attribute_int("fit_verdicts_n"));
  } catch (const std::exception&) {
    return "";
  }
  if (consulted(now, s).checksum() == recorded) return "";
  return "the verdicts its fit consults (phi_init, finite_size: fit_verdicts in stats.h5) changed";
}

}  // namespace jam::stats
