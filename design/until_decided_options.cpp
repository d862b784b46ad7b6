#include "design/until_decided_options.hpp"

#include <fmt/format.h>

#include <variant>

#include "checks/check_registry.hpp"
#include "design/check_stage.hpp"
#include "design/judging_options.hpp"

namespace jam::design {
namespace {

using nlohmann::json;

/// A recorded value as the messages show it: numbers as %g, null as "none".
std::string shown(const json& v) {
  if (v.is_null()) return "none";
  if (v.is_number()) return fmt::format("{:g}", v.get<double>());
  if (v.is_array()) {
    std::string out;
    for (const auto& e : v) out += (out.empty() ? "" : ", ") + shown(e);
    return "[" + out + "]";
  }
  return v.is_string() ? v.get<std::string>() : v.dump();
}

/// "" when equal; else "<what> <now> differs from the recorded <recorded>".
std::string differs(const std::string& what, const json& recorded, const json& now) {
  if (recorded == now) return "";
  return fmt::format("{} {} differs from the {} it was begun with", what, shown(now),
                     shown(recorded));
}

/// Whether a look's verdicts hold `e`'s (until_decided_look.cpp, judge_question): without
/// checks in the question, the statistical checks of `all` and their parts
/// (checks::run_check("all")); with them, every check of stats.h5 (and part of one) the
/// question names, in `all` or not.
bool judged_by_a_look(const CampaignQuestion& question, const checks::CheckEntry& e) {
  if (std::holds_alternative<checks::LammpsCheck>(e.run)) return false;
  if (question.checks.empty()) return e.in_all;
  const checks::CheckEntry* runs = &e;
  if (const auto* part = std::get_if<checks::PartOf>(&e.run))
    runs = checks::find_check(part->check);
  return runs && std::holds_alternative<checks::StatsCheck>(runs->run) &&
         question_wants(question.checks, std::string(e.name));
}

}  // namespace

checks::CheckOptions sequence_check_options(const Campaign& c, const CampaignQuestion& question) {
  return check_options(JudgingArgs{}, "all", c.margins, c.regions, question);
}

json sequence_record(const Campaign& c, const CampaignQuestion& question, double alpha) {
  const checks::CheckOptions o = sequence_check_options(c, question);
  json margins = json::object(), judged = json::array();
  for (const auto& e : checks::check_registry()) {
    margins[std::string(e.name)] = o.margin(std::string(e.name));
    if (judged_by_a_look(question, e)) judged.push_back(std::string(e.name));
  }
  const json range_asked =
      question.states_range() ? json{{"phi_min", *question.phi_min}, {"phi_max", *question.phi_max}}
                              : json(nullptr);
  return {{"alpha", alpha},
          {"margins", margins},
          {"regions",
           {{"phi_j", o.phi_j ? json(*o.phi_j) : json(nullptr)},
            {"near", o.regions.near},
            {"far", o.regions.far}}},
          {"checks", judged},
          {"question", range_asked}};
}

std::string sequence_difference(const json& recorded, const json& now) {
  if (auto why = differs("--alpha", recorded.value("alpha", json()), now.at("alpha")); !why.empty())
    return why;
  const json margins = recorded.value("margins", json::object());
  for (const auto& [check, margin] : now.at("margins").items()) {
    const std::string what = fmt::format("the margin of {} (the campaign file's [margins])", check);
    if (auto why = differs(what, margins.value(check, json()), margin); !why.empty()) return why;
  }
  const json regions = recorded.value("regions", json::object());
  for (const auto& [key, value] : now.at("regions").items()) {
    const std::string what = fmt::format("[regions] {}", key);
    if (auto why = differs(what, regions.value(key, json()), value); !why.empty()) return why;
  }
  // The range asked; a state begun before it was recorded asked none.
  const json asked = recorded.value("question", json());
  for (const char* key : {"phi_min", "phi_max"}) {
    const json was = asked.is_object() ? asked.value(key, json()) : json();
    const json is = now.at("question").is_object() ? now.at("question").at(key) : json();
    const std::string what = fmt::format("the range asked's {} ([question] {}, or --{})", key, key,
                                         key == std::string("phi_min") ? "phi-min" : "phi-max");
    if (auto why = differs(what, was, is); !why.empty()) return why;
  }
  return differs("the checks judged", recorded.value("checks", json()), now.at("checks"));
}

}  // namespace jam::design
