// The registry's table expanded into entries, and everything derived from it: default margins,
// running checks by name, the listing.
#include "checks/check_registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "checks/checks.hpp"
#include "checks/lammps_check.hpp"
#include "checks/regression_check.hpp"
#include "checks/run_checks.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict_ensembles.hpp"

namespace jam::checks {

// The run column is a kind (stats, baseline, lammps) or part(parent); pasted onto a prefix it
// names the macro below that declares `<name>_check` with its kind's signature, or gives the
// entry's CheckRun. part(parent) pastes to a macro of the parent that leaves behind
// JAM_CHECK_DROP, which swallows the (name) that follows it.
#define JAM_CHECK_DROP(name)
#define JAM_CHECK_DECLARE_stats(name) \
  std::vector<Verdict> name##_check(const StatsData&, const CheckOptions&);
#define JAM_CHECK_DECLARE_baseline(name)                                                     \
  std::vector<Verdict> name##_check(const StatsData&, const StatsData&, const CheckOptions&, \
                                    const RegressionOptions&);
#define JAM_CHECK_DECLARE_lammps(name) std::vector<Verdict> name##_check(const LammpsCheckOptions&);
#define JAM_CHECK_DECLARE_part(parent) JAM_CHECK_DROP
#define JAM_CHECK_DECLARE(name, run, ...) JAM_CHECK_DECLARE_##run(name)
JAM_CHECK_TABLE(JAM_CHECK_DECLARE)

namespace {

// clang-format off
#define JAM_CHECK_RUN_stats(name) CheckRun(StatsCheck(&name##_check))
#define JAM_CHECK_RUN_baseline(name) CheckRun(BaselineCheck(&name##_check))
#define JAM_CHECK_RUN_lammps(name) CheckRun(LammpsCheck(&name##_check))
#define JAM_CHECK_RUN_part(parent) CheckRun(PartOf{#parent}) JAM_CHECK_DROP
#define JAM_CHECK_ENTRY(name, run, margin, unit, reason, in_all, figure, samples_of)              \
  CheckEntry{#name, JAM_CHECK_RUN_##run(name), margin, MarginUnit::unit, margin_reasons::reason,  \
             in_all, figure, &samples::samples_of},
// clang-format on
const CheckEntry kRegistry[] = {JAM_CHECK_TABLE(JAM_CHECK_ENTRY)};
// Not left to the other files of a unity batch.
#undef JAM_CHECK_ENTRY
#undef JAM_CHECK_RUN_part
#undef JAM_CHECK_RUN_lammps
#undef JAM_CHECK_RUN_baseline
#undef JAM_CHECK_RUN_stats
#undef JAM_CHECK_DECLARE
#undef JAM_CHECK_DECLARE_part
#undef JAM_CHECK_DECLARE_lammps
#undef JAM_CHECK_DECLARE_baseline
#undef JAM_CHECK_DECLARE_stats
#undef JAM_CHECK_DROP

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
// Spelled out: clang before 17 has no deduction of aggregate template arguments (P1816).
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

/// The kind of a check as the listing names it.
std::string kind(const CheckEntry& e) {
  return std::visit(Overloaded{[](StatsCheck) { return std::string("stats"); },
                               [](BaselineCheck) { return std::string("baseline"); },
                               [](LammpsCheck) { return std::string("lammps"); },
                               [](PartOf p) { return "part of " + std::string(p.check); }},
                    e.run);
}

std::string unit_name(MarginUnit u) {
  return u == MarginUnit::relative ? "relative" : "packing_fraction";
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// The stats checks run_check() accepts, then "all".
std::vector<std::string> stats_check_names() {
  std::vector<std::string> out;
  for (const auto& e : kRegistry)
    if (std::holds_alternative<StatsCheck>(e.run)) out.emplace_back(e.name);
  out.emplace_back("all");
  return out;
}

void append(std::vector<Verdict>& to, const std::vector<Verdict>& more) {
  to.insert(to.end(), more.begin(), more.end());
}

}  // namespace

std::span<const CheckEntry> check_registry() {
  return kRegistry;
}

const CheckEntry* find_check(std::string_view name) {
  const auto it = std::find_if(std::begin(kRegistry), std::end(kRegistry),
                               [&](const CheckEntry& e) { return e.name == name; });
  return it == std::end(kRegistry) ? nullptr : &*it;
}

bool runs_by_name(const CheckEntry& e) {
  return !std::holds_alternative<PartOf>(e.run);
}

std::vector<std::string> command_names() {
  std::vector<std::string> out;
  for (const auto& e : kRegistry)
    if (runs_by_name(e)) out.emplace_back(e.name);
  out.emplace_back("all");
  return out;
}

double default_margin(const std::string& check) {
  if (const CheckEntry* e = find_check(check)) return e->default_margin;
  throw std::invalid_argument(fmt::format("check '{}': no margin defined", check));
}

std::vector<Verdict> run_check(const std::string& name, const StatsData& d, const CheckOptions& o) {
  const CheckEntry* named = find_check(name);
  if (name != "all" && !(named && std::holds_alternative<StatsCheck>(named->run)))
    throw std::invalid_argument(
        fmt::format("check '{}': unknown ({})", name, joined(stats_check_names())));
  std::vector<Verdict> out;
  for (const auto& e : kRegistry) {
    const auto* f = std::get_if<StatsCheck>(&e.run);
    if (f && (&e == named || (name == "all" && e.in_all))) append(out, (*f)(d, o));
  }
  return out;
}

std::vector<Verdict> run_checks(const std::string& name, const CheckInputs& in) {
  std::vector<const CheckEntry*> chosen;
  for (const auto& e : kRegistry) {
    const bool of_jam = std::holds_alternative<LammpsCheck>(e.run);
    if (runs_by_name(e) && (e.name == name || (name == "all" && e.in_all &&
                                               !(of_jam && in.runs_of_another_simulator))))
      chosen.push_back(&e);
  }
  if (chosen.empty() && name != "all")
    throw std::invalid_argument(
        fmt::format("check '{}': unknown ({})", name, joined(command_names())));
  std::optional<StatsData> stats;  // DIR/stats.h5, read when a check first needs it
  auto read = [&]() -> const StatsData& {
    if (!stats) stats = read_stats(in.directory);
    return *stats;
  };
  std::vector<Verdict> out;
  for (const CheckEntry* e : chosen) {
    const std::string check(e->name);
    append(out, std::visit(Overloaded{[&](StatsCheck f) { return f(read(), in.options); },
                                      [&](BaselineCheck f) {
                                        if (in.baseline_directory.empty())
                                          throw std::runtime_error(fmt::format(
                                              "{}: --against BASELINE_DIR is required", check));
                                        if (!(in.regression.tolerance >= 0))
                                          throw std::runtime_error(
                                              fmt::format("--tolerance {:g}: must be >= 0",
                                                          in.regression.tolerance));
                                        return f(read(), read_stats(in.baseline_directory),
                                                 in.options, in.regression);
                                      },
                                      [&](LammpsCheck f) {
                                        LammpsCheckOptions l = in.lammps;
                                        l.margin = in.options.margin(check);
                                        return f(l);
                                      },
                                      // Never chosen: its parent writes these verdicts.
                                      [](PartOf) { return std::vector<Verdict>{}; }},
                           e->run));
  }
  return out;
}

std::string registry_json() {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& e : kRegistry) {
    const auto* part = std::get_if<PartOf>(&e.run);
    out.push_back({{"name", std::string(e.name)},
                   {"kind", part ? "part" : kind(e)},
                   {"part_of", part ? nlohmann::json(std::string(part->check)) : nullptr},
                   {"default_margin", e.default_margin},
                   {"margin_unit", unit_name(e.margin_unit)},
                   {"margin_reason", std::string(e.margin_reason)},
                   {"in_all", e.in_all},
                   {"figure", std::string(e.figure)}});
  }
  return out.dump(2) + "\n";
}

std::string registry_table() {
  std::ostringstream out;
  // The name and kind columns as wide as their longest entries (compare_fit_phi_j).
  std::size_t name_width = 14, kind_width = 17;
  for (const auto& e : kRegistry) {
    name_width = std::max(name_width, e.name.size());
    kind_width = std::max(kind_width, kind(e).size());
  }
  out << fmt::format("{:<{}} {:<{}} {:>7} {:<17} {:<4} {:<15} {}\n", "check", name_width, "kind",
                     kind_width, "margin", "unit", "all", "report figure", "why that margin");
  for (const auto& e : kRegistry) {
    out << fmt::format("{:<{}} {:<{}} {:>7g} {:<17} {:<4} {:<15} {}\n", e.name, name_width, kind(e),
                       kind_width, e.default_margin, unit_name(e.margin_unit),
                       e.in_all ? "yes" : "no", e.figure, e.margin_reason);
  }
  return out.str();
}

}  // namespace jam::checks
