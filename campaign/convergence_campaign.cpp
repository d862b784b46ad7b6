#include "campaign/convergence_campaign.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "campaign/toml_file.hpp"
#include "sim/dynamics/integrator_list.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {
namespace {

/// The compression tolerance a run of `c` at `log10_rate` uses, in its own error norm.
double resolved_tolerance(const Campaign& c, double log10_rate) {
  if (c.run.tolerance != "auto") return std::stod(c.run.tolerance);
  return auto_tolerance(std::pow(10.0, log10_rate), c.run.dense_output, c.run.rms_error_norm());
}

template <class T>
toml::array array_of(const std::vector<T>& values) {
  toml::array a;
  for (const T& v : values) a.push_back(v);
  return a;
}

}  // namespace

std::string convergence_campaign_text(const Campaign& c, const ConvergenceChoice& choice) {
  auto fail = [&c](const std::string& what) {
    throw CampaignError(fmt::format("{}: convergence: {}", c.source_path, what));
  };
  const std::vector<std::int64_t> sizes = choice.sizes.empty() ? c.sizes : choice.sizes;
  for (auto n : sizes)
    if (std::find(c.sizes.begin(), c.sizes.end(), n) == c.sizes.end())
      fail(fmt::format("size {} is not one of the campaign's", n));
  std::vector<double> rates = choice.log10_rates;
  if (rates.empty()) {
    rates = c.log10_rates;
    std::sort(rates.begin(), rates.end());
    rates.resize(std::min<std::size_t>(2, rates.size()));
  }
  for (double r : rates)
    if (std::find(c.log10_rates.begin(), c.log10_rates.end(), r) == c.log10_rates.end())
      fail(fmt::format("rate 1e{:g} is not one of the campaign's", r));
  if (choice.samples < 2 || choice.samples > c.samples)
    fail(fmt::format("{} samples: at least 2 and at most the campaign's {}", choice.samples,
                     c.samples));
  if (!(choice.tolerance_factor > 0 && choice.tolerance_factor < 1))
    fail(fmt::format("tolerance factor {:g}: must be in (0, 1)", choice.tolerance_factor));
  // A fixed-step integrator (euler, heun) is redone by its dynamics' error-controlled one at a
  // tenth of that one's default tolerance: what converged means does not depend on the step the
  // campaign took. A dynamics without one has no stricter setting to name.
  const std::string_view adaptive = adaptive_integrator_of(c.run.dynamics);
  if (adaptive.empty())
    fail(fmt::format("dynamics '{}' has no error-controlled integrator to redo its runs with",
                     c.run.dynamics));
  const bool kept = c.run.resolved_integrator() == adaptive;
  double tolerance = HUGE_VAL;
  for (double r : rates)
    tolerance =
        std::min(tolerance, kept ? resolved_tolerance(c, r)
                                 : auto_tolerance(std::pow(10.0, r), c.run.dense_output, false));
  tolerance *= choice.tolerance_factor;

  toml::table t = toml::parse(c.source_text);
  const std::string output = choice.output.empty() ? c.output + "-convergence" : choice.output;
  t.insert_or_assign("name", c.name + "-convergence");
  t.insert_or_assign("output", output);
  t.insert_or_assign("sizes", array_of(sizes));
  t.insert_or_assign("log10_rates", array_of(rates));
  t.insert_or_assign("samples", choice.samples);
  t.insert_or_assign("tolerance", fmt::format("{:.3g}", tolerance));
  t.insert_or_assign("error_norm", "max");
  if (!kept) {
    t.insert_or_assign("integrator", std::string(adaptive));
    t.erase("dt");
  }
  if (choice.phi_stop) t.insert_or_assign("phi_stop", *choice.phi_stop);
  if (!c.chain_phi_init.empty()) {
    std::vector<double> chain;  // the packings of the starts of the rates redone
    for (double r : rates)
      chain.push_back(c.chain_phi_init[static_cast<std::size_t>(
          std::find(c.log10_rates.begin(), c.log10_rates.end(), r) - c.log10_rates.begin())]);
    t.insert_or_assign("chain_phi_init", array_of(chain));
    t.insert_or_assign("chain_starts_from", c.output);
  }
  // Judged against the campaign (`jam check convergence`), not on their own.
  t.erase("compare_with");
  t.erase("expected_failures");
  std::ostringstream text;
  text << "# The convergence runs of campaign " << c.name
       << " (jam campaign converge): " << choice.samples << " samples, compression tolerance "
       << fmt::format("{:.3g}", tolerance) << " in the largest component\n# (a factor "
       << choice.tolerance_factor
       << " of the campaign's), the same starts. Judge with\n#   jam check convergence " << c.output
       << " --against " << output << "\n"
       << toml_text(t) << "\n";
  // Read back: what is written must be a campaign file like any other.
  parse_campaign(text.str(), c.source_path);
  return text.str();
}

std::string write_convergence_campaign(const Campaign& c, const std::string& text,
                                       const std::string& out) {
  {
    AtomicFile file(out);
    std::fputs(text.c_str(), file.stream());
    file.commit();
  }
  const Campaign written = read_campaign(out);
  return fmt::format(
      "wrote {}: {} runs of {} redone\nthen:\n  jam campaign run {}\n  jam stats {}\n"
      "  jam check convergence {} --against {}\n",
      out,
      written.samples * written.sizes.size() * written.phi_init.size() * written.log10_rates.size(),
      c.name, out, written.output, c.output, written.output);
}

}  // namespace jam
