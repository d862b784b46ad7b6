#include "design/judging_options.hpp"

#include <fmt/format.h>

#include <cmath>

#include "checks/check_registry.hpp"

namespace jam::design {
namespace {

/// --margin's help: the default margins and which are packing differences, from the registry.
std::string margin_help() {
  const double usual = checks::default_margin(checks::command_names().front());
  std::string other, packing;
  for (const auto& e : checks::check_registry()) {
    if (e.default_margin != usual)
      other += fmt::format("{}{} {:g}", other.empty() ? "" : ", ", e.name, e.default_margin);
    if (e.margin_unit == checks::MarginUnit::packing_fraction)
      packing += (packing.empty() ? "" : ", ") + std::string(e.name);
  }
  return fmt::format(
      "Margin M of the named check (all, and jam pipeline: of every check): the largest "
      "effect that still passes, a relative pressure difference ({}: a packing difference). "
      "Default: the campaign file's [margins], else {:g} ({})",
      packing, usual, other);
}

bool packing(std::optional<double> phi) {
  return !phi || (std::isfinite(*phi) && *phi > 0 && *phi < 1);
}

std::vector<JudgingOption> make_table() {
  return {
      {"--alpha", "alpha", &JudgingArgs::alpha,
       fmt::format("False-alarm rate of each check (Bonferroni over its comparisons; default: "
                   "the campaign file's [question] alpha, else {:g})",
                   kDefaultAlpha),
       [](const JudgingArgs& a) {
         return !a.alpha || (*a.alpha > 0 && *a.alpha < 1) ? "" : std::string("must be in (0, 1)");
       }},
      {"--permutations", "permutations", &JudgingArgs::permutations,
       "Permutations of whole runs for null distributions",
       [](const JudgingArgs& a) {
         return a.permutations >= 100 ? "" : std::string("must be at least 100");
       }},
      {"--phi-min", "phi_min", &JudgingArgs::phi_min,
       "Pressure checks (finite_size, phi_init, chain, compare): judge from this packing. "
       "Where the campaign file states a range ([question] phi_min, phi_max) it replaces "
       "that range's lower end, judged as the region \"asked\"; else the pooled verdicts "
       "pool from it (default: the scaling fit's window in stats.h5; compare: REF's)",
       [](const JudgingArgs& a) {
         return packing(a.phi_min) ? "" : std::string("must be a packing in (0, 1)");
       }},
      {"--phi-max", "phi_max", &JudgingArgs::phi_max,
       "Pressure checks (finite_size, phi_init, compare): judge up to this packing (as "
       "--phi-min: the upper end of the range asked, or of the pooled range)",
       [](const JudgingArgs& a) {
         if (!packing(a.phi_max)) return std::string("must be a packing in (0, 1)");
         if (a.phi_min && a.phi_max && !(*a.phi_min < *a.phi_max))
           return fmt::format("must exceed --phi-min {}", *a.phi_min);
         return std::string();
       }},
      {"--phi-j", "phi_j", &JudgingArgs::phi_j,
       "Pressure checks: the packing the regions below, at and above jamming are placed "
       "around (default: the campaign file's [regions] phi_j, else the scaling fit's phi_J "
       "in stats.h5, else <phi_Ji> of the largest size, else where its <Z> crosses 2D; "
       "none: no regions)",
       [](const JudgingArgs& a) {
         return packing(a.phi_j) ? "" : std::string("must be a packing in (0, 1)");
       }},
      {"--region-near", "region_near", &JudgingArgs::region_near,
       "Half-width of the region at jamming, phi_J +- near; the regions below and above "
       "reach from it to --region-far",
       [](const JudgingArgs& a) {
         return !a.region_near || (*a.region_near > 0 && *a.region_near < 0.1)
                    ? ""
                    : std::string("must be in (0, 0.1)");
       }},
      {"--region-far", "region_far", &JudgingArgs::region_far,
       "Outer edge of the regions below and above jamming, phi_J -+ far",
       [](const JudgingArgs& a) {
         if (!a.region_far) return std::string();
         if (!(*a.region_far > 0 && *a.region_far < 0.2)) return std::string("must be in (0, 0.2)");
         const double near = a.region_near.value_or(checks::RegionOffsets{}.near);
         if (!(*a.region_far > near)) return fmt::format("must exceed --region-near {:g}", near);
         return std::string();
       }},
      {"--margin", "margin", &JudgingArgs::margin, margin_help(),
       [](const JudgingArgs& a) {
         return !a.margin || (std::isfinite(*a.margin) && *a.margin > 0)
                    ? ""
                    : std::string("must be a finite number > 0");
       }},
      {"--reference-dir", "reference_dir", &JudgingArgs::reference_dir,
       "lammps: LAMMPS inputs and stored results", [](const JudgingArgs&) { return ""; }},
      {"--no-lmp", "no_lmp", &JudgingArgs::no_lmp,
       "lammps: use the stored LAMMPS result even if lmp is installed",
       [](const JudgingArgs&) { return ""; }},
      {"--with-lammps", "with_lammps", &JudgingArgs::with_lammps,
       "all: also the LAMMPS self-checks (the lammps check: jam against LAMMPS on stored "
       "inputs, about 20 s when lmp runs; a test of jam, not of the campaign's data); without "
       "it only `jam check lammps DIR` or [question] checks naming lammps judge them",
       [](const JudgingArgs&) { return ""; }},
  };
}

/// An option's value as the record gives it (null: not given).
nlohmann::json value_of(const JudgingArgs& a, const JudgingOption& o) {
  return std::visit(
      [&a](auto field) -> nlohmann::json {
        const auto& value = a.*field;
        if constexpr (requires { value.has_value(); })
          return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
        else
          return value;
      },
      o.field);
}

}  // namespace

const std::vector<JudgingOption>& judging_options() {
  static const std::vector<JudgingOption> table = make_table();
  return table;
}

void validate_judging(const JudgingArgs& args) {
  for (const auto& o : judging_options()) {
    const std::string rule = o.broken(args);
    if (rule.empty()) continue;
    const std::string value = std::visit(
        [&args](auto field) {
          const auto& v = args.*field;
          if constexpr (requires { v.has_value(); })
            return v ? fmt::format("{:g}", *v) : std::string();
          else
            return fmt::format("{}", v);
        },
        o.field);
    throw std::runtime_error(fmt::format("{} {}: {}", o.flag, value, rule));
  }
}

checks::CheckOptions check_options(const JudgingArgs& args, const std::string& name,
                                   const std::map<std::string, double>& campaign_margins,
                                   const std::map<std::string, double>& campaign_regions,
                                   const CampaignQuestion& question) {
  validate_judging(args);
  checks::CheckOptions o;
  o.alpha = args.alpha.value_or(question.alpha.value_or(kDefaultAlpha));
  o.permutations = args.permutations;
  if (question.states_range()) {
    // The question's range is judged as the region "asked" beside the pooled verdict (which
    // keeps its own range); the command line's ends replace the question's.
    o.regions.asked_min = args.phi_min.value_or(*question.phi_min);
    o.regions.asked_max = args.phi_max.value_or(*question.phi_max);
    if (args.phi_min || args.phi_max)
      o.regions.asked_from = args.phi_min && args.phi_max
                                 ? "--phi-min, --phi-max"
                                 : "[question] phi_min, phi_max with --phi-min or --phi-max";
    if (!(*o.regions.asked_min < *o.regions.asked_max))
      throw std::runtime_error(
          fmt::format("the range asked [{:g}, {:g}] ({}): phi_min must lie below phi_max",
                      *o.regions.asked_min, *o.regions.asked_max, o.regions.asked_from));
  } else {
    o.phi_min = args.phi_min;
    o.phi_max = args.phi_max;
  }
  auto campaign = [&campaign_regions](const char* key) -> std::optional<double> {
    const auto it = campaign_regions.find(key);
    return it == campaign_regions.end() ? std::nullopt : std::optional<double>(it->second);
  };
  o.phi_j = args.phi_j ? args.phi_j : campaign("phi_j");
  o.regions.near = args.region_near.value_or(campaign("near").value_or(o.regions.near));
  o.regions.far = args.region_far.value_or(campaign("far").value_or(o.regions.far));
  if (!(o.regions.far > o.regions.near))
    throw std::runtime_error(
        fmt::format("regions: far {:g} must exceed near {:g}", o.regions.far, o.regions.near));
  o.margins = campaign_margins;
  if (args.margin) {
    // `all` sets the margin of every check in the unit of the named one (relative pressure
    // differences when all); a check sets its own and those of its parts measured in the same
    // unit (compare: compare_fit, not compare_jamming, a packing difference).
    const checks::CheckEntry* named = checks::find_check(name == "all" ? "finite_size" : name);
    for (const auto& e : checks::check_registry()) {
      const auto* part = std::get_if<checks::PartOf>(&e.run);
      const bool same_unit = named && e.margin_unit == named->margin_unit;
      if (same_unit && (name == "all" || name == e.name || (part && name == part->check)))
        o.margins[std::string(e.name)] = *args.margin;
    }
  }
  return o;
}

nlohmann::json question_record(const CampaignQuestion& question,
                               const checks::CheckOptions& options) {
  using nlohmann::json;
  json range = nullptr;
  if (options.regions.asks())
    range = {{"phi_min", *options.regions.asked_min},
             {"phi_max", *options.regions.asked_max},
             {"from", options.regions.asked_from}};
  json margins = json::object();
  for (const auto& e : checks::check_registry())
    margins[std::string(e.name)] = options.margin(std::string(e.name));
  // Without a range asked, what the pooled verdicts judge instead.
  const char* pooled = options.phi_min || options.phi_max
                           ? "the range given (--phi-min, --phi-max)"
                           : "the scaling fit's window, else the whole compression";
  return {{"range", range},
          {"pooled", pooled},
          {"checks", question.checks.empty() ? json(nullptr) : json(question.checks)},
          {"margins", margins},
          {"alpha", options.alpha}};
}

nlohmann::json judging_record(const JudgingArgs& args, const checks::CheckOptions& options,
                              const CampaignQuestion& question) {
  nlohmann::json record = nlohmann::json::object();
  for (const auto& o : judging_options()) record[o.key] = value_of(args, o);
  record["alpha"] = options.alpha;  // as used: --alpha, else [question] alpha, else the default
  nlohmann::json margins = nlohmann::json::object();
  for (const auto& e : checks::check_registry())
    margins[std::string(e.name)] = options.margin(std::string(e.name));
  record["margins"] = margins;
  // The regions as used (the campaign's [regions] where no option gave them).
  record["regions"] = {
      {"phi_j", options.phi_j ? nlohmann::json(*options.phi_j) : nlohmann::json(nullptr)},
      {"near", options.regions.near},
      {"far", options.regions.far}};
  record["question"] = question_record(question, options);
  return record;
}

}  // namespace jam::design
