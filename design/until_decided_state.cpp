#include "design/until_decided_state.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "checks/verdict_file.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"

namespace jam::design {
namespace fs = std::filesystem;
using nlohmann::json;

std::string state_path(const Campaign& c) {
  return (fs::path(c.output) / "until-decided.json").string();
}

State read_state(const Campaign& c) {
  State s;
  const std::string path = state_path(c);
  if (!fs::exists(fs::symlink_status(path))) return s;
  check_input_file("until-decided state", path);
  std::ifstream in(path);
  json j;
  try {
    j = json::parse(in);
    s.looks = j.at("looks");
    s.decided = j.at("decided");
    s.finished = j.at("finished").get<bool>();
    s.outcome = j.at("outcome").get<std::string>();
    s.options = j.value("options", json());
    for (const auto& e : j.at("samples")) {
      s.next[{e.at("n").get<std::int64_t>(), e.at("phi_init").get<double>(),
              e.at("log10_rate").get<double>()}] = e.at("samples").get<std::int64_t>();
    }
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not an until-decided state ({})", path, e.what()));
  }
  if (!s.looks.is_array() || !s.decided.is_object())
    throw std::runtime_error(fmt::format("{}: not an until-decided state", path));
  return s;
}

void write_state(const Campaign& c, const State& s) {
  json samples = json::array();
  for (const auto& [id, count] : s.next) {
    samples.push_back({{"n", id.n},
                       {"phi_init", id.phi_init},
                       {"log10_rate", id.log10_rate},
                       {"samples", count}});
  }
  const json j{{"looks", s.looks},       {"decided", s.decided}, {"samples", samples},
               {"finished", s.finished}, {"outcome", s.outcome}, {"options", s.options}};
  AtomicFile out(state_path(c));
  std::fputs((j.dump(1) + "\n").c_str(), out.stream());
  out.commit();
  write_added_samples(c, s.next);
}

void record_decided(State& s, const std::string& identity, const checks::Verdict& v, int look) {
  json record = checks::verdict_json(v);
  record["look"] = look;
  s.decided[identity] = std::move(record);
}

void restore_decided(const json& decided, checks::Verdict& v) {
  const checks::Verdict was = checks::verdict_from_json(decided);
  v.status = decided.at("status").get<std::string>();
  v.reason = decided.at("reason").get<std::string>();
  v.statistic = was.statistic;
  v.threshold = was.threshold;
  v.excluded_above = was.excluded_above;
  v.excluded_below = was.excluded_below;
  v.estimate = was.estimate;
  v.detectable = was.detectable;
  // States written before decided verdicts took their checks.json form name it "detectable".
  if (!decided.contains("detectable_effect")) {
    const json old = decided.value("detectable", json());
    v.detectable = old.is_number() ? old.get<double>() : NAN;
  }
  v.samples_needed = NAN;
  v.values["look"] = decided.at("look").get<double>();
}

}  // namespace jam::design
