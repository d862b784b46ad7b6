#include "checks/compare_diagnosis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "campaign/campaign_dir.hpp"
#include "campaign/external_campaign.hpp"
#include "checks/compare_coverage.hpp"

namespace jam::checks {
namespace {

bool same_number(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b));
}

/// "overdamped", or "inertial (Q 2)".
std::string dynamics_words(const SideModel& m) {
  return m.dynamics == "inertial" ? fmt::format("inertial (Q {:g})", m.quality_factor) : m.dynamics;
}

}  // namespace

std::optional<SideModel> campaign_model(const std::string& directory) {
  if (directory.empty()) return std::nullopt;
  try {
    if (is_external_campaign(directory)) {
      const ExternalCampaign c = read_external_campaign(directory);
      return SideModel{c.dim, c.diameter_ratio, c.contact, c.dynamics, c.quality_factor};
    }
    if (std::filesystem::exists(std::filesystem::path(directory) / "campaign.toml")) {
      const Campaign c = stored_campaign(directory);
      return SideModel{c.run.dim, c.run.diameter_ratio, c.run.contact, c.run.dynamics,
                       c.run.quality_factor};
    }
  } catch (const std::exception&) {
    // A record that does not read says nothing of the model; the statistics name it.
  }
  return std::nullopt;
}

std::string model_difference(const SideModel& dir, const SideModel& ref) {
  std::vector<std::string> parts;
  if (dir.dim != ref.dim) parts.push_back(fmt::format("dimension {} against {}", dir.dim, ref.dim));
  if (!same_number(dir.diameter_ratio, ref.diameter_ratio))
    parts.push_back(
        fmt::format("diameter_ratio {:g} against {:g}", dir.diameter_ratio, ref.diameter_ratio));
  if (dir.contact != ref.contact)
    parts.push_back(fmt::format("contact {} against {}", dir.contact, ref.contact));
  // Q matters only to inertial dynamics (an overdamped record may carry any).
  const bool quality_factor_differs = dir.dynamics == "inertial" && ref.dynamics == "inertial" &&
                                      !same_number(dir.quality_factor, ref.quality_factor);
  if (dir.dynamics != ref.dynamics || quality_factor_differs)
    parts.push_back(
        fmt::format("dynamics {} against {}", dynamics_words(dir), dynamics_words(ref)));
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

void name_model_difference(std::vector<Verdict>& out, const std::optional<SideModel>& dir,
                           const std::optional<SideModel>& ref) {
  if (!dir || !ref) return;
  const std::string differs = model_difference(*dir, *ref);
  if (differs.empty()) return;
  for (Verdict& v : out) {
    v.reason += fmt::format(
        "; the two sides' models differ (DIR against REF, as their campaign directories record "
        "them): {}: a difference found here may be the model's, not the code's "
        "(docs/porting.md, \"The model, exactly\")",
        differs);
    v.values["model_differs"] = 1.0;
  }
}

void say_if_only_at_start(Verdict& v, const PoolRange& asked, double past_start,
                          const RangeData& data, Levels levels, double margin, int permutations) {
  if (v.status != "fail" || !v.values.count("range_min") || !v.values.count("range_max")) return;
  const double lo = v.values.at("range_min"), hi = v.values.at("range_max");
  // The start inside the range judged, and most of that range past it: a sliver judged again
  // says nothing of where the difference lies.
  if (!(lo < past_start && hi - past_start >= kNarrowShare * (hi - lo))) return;
  PoolRange past = asked;
  past.min = std::max(asked.min, past_start);
  past.whole = false;
  Verdict base = v;
  base.values.clear();
  base.curves.clear();
  const std::vector<Verdict> again =
      judge_by_region(base, data, past, {}, {}, levels, margin, permutations, 3, RelativeTo::b);
  // Judged again, and not failing: a range with nothing to judge (no values) is no evidence.
  if (again.empty() || again.front().status == "fail" || !again.front().values.count("difference"))
    return;
  const Verdict& after = again.front();
  const std::string variable = asked.variable;
  v.values["start_only"] = 1.0;
  v.values["past_start"] = past_start;
  v.reason = fmt::format(
      "fails only just after the start, a sign of another start protocol: judged from {} "
      "{:.4g} on ({:g} in packing past where the compression takes over) the same comparison "
      "is {} (Delta p/p {}); a start relaxed otherwise than jam's (CG minimisation, another "
      "energy target) differs there first: relax each start with damped dynamics as jam does "
      "(docs/porting.md, \"Relax the start with damped dynamics, not CG minimisation\"); {}",
      variable, past_start, kStartSection, after.status, effect_text(after, after.estimate, true),
      v.reason);
}

std::string too_few_samples(std::size_t dir, std::size_t ref, const std::string& what) {
  if (dir >= 2 && ref >= 2) return "";
  const std::string counts =
      dir < 2 && ref < 2
          ? fmt::format("DIR has {}{}, REF has {}", dir, what, ref)
          : fmt::format("{} has {}{}", dir < 2 ? "DIR" : "REF", dir < 2 ? dir : ref, what);
  return fmt::format("needs at least 2 samples per set ({})", counts);
}

}  // namespace jam::checks
