#include "stats/run_curves.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <functional>
#include <optional>

#include "campaign/campaign_dir.hpp"
#include "campaign/external_campaign.hpp"
#include "campaign/manifest.hpp"
#include "campaign/run_plan.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/terminal_text.hpp"

namespace jam::stats {

namespace {

/// The runs of an external campaign (campaign/external_campaign.hpp), each checked again as an
/// open run and against the checksum it was imported with; a run that fails is left out with a
/// warning naming it, as a corrupt planned run is.
CampaignData read_external_runs(const std::string& directory) {
  const ExternalCampaign campaign = read_external_campaign(directory);
  CampaignData data;
  data.name = campaign.name;
  data.dim = campaign.dim;
  data.phi_step = campaign.phi_step;
  for (const std::string& path : unlisted_run_files(directory, campaign))
    fmt::print(stderr, "jam stats: warning: {} is not in external.toml: not averaged\n",
               visible(path));
  for (const ExternalRun& run : campaign.runs) {
    OpenRun r;
    if (const std::string why = stored_run_problem(directory, run, &r); !why.empty()) {
      fmt::print(stderr, "jam stats: warning: corrupt run {} left out: {}\n", visible(run.name),
                 visible(why));
      data.skipped.push_back(fmt::format("{} (corrupt)", run.name));
      continue;
    }
    RunCurves c;
    c.n = run.n;
    c.phi_init = run.phi_init;
    c.log10_rate = run.log10_rate;
    c.sample = run.sample;
    c.phi = std::move(r.packing_fraction);
    c.pressure = std::move(r.pressure);
    c.contacts = std::move(r.contacts_per_particle);  // empty: no constant-Z averages
    c.jamming_point = r.jamming_packing_fraction;
    data.runs.push_back(std::move(c));
  }
  return data;
}

}  // namespace

namespace {

/// One finished run's curves from its file (run_status or manifest_run_status judged it).
RunCurves read_run_curves(const std::string& file, std::int64_t n, double phi_init,
                          double log10_rate, std::int64_t sample) {
  const h5::File f = h5::File::open_read(file);
  RunCurves c;
  c.n = n;
  c.phi_init = phi_init;
  c.log10_rate = log10_rate;
  c.sample = sample;
  // The status has checked the file; the lengths are checked again where they are read.
  c.phi = f.read_dataset("packing_fraction");
  const h5::Extent points = h5::exactly(c.phi.size());
  c.pressure = f.read_dataset("pressure", points);
  c.contacts = f.read_dataset("contacts_per_particle", points);
  if (f.has_dataset("contacts_per_particle_no_rattlers")) {
    c.contacts_no_rattlers = f.read_dataset("contacts_per_particle_no_rattlers", points);
  }
  if (f.has_attribute("jamming_packing_fraction")) {
    c.jamming_point = f.read_attribute_double("jamming_packing_fraction");
  }
  return c;
}

/// Takes or leaves out one run by its status, as both ways of listing the runs do.
void take_run(CampaignData& data, const std::string& name, RunStatus status,
              const std::string& detail, const std::function<RunCurves()>& read) {
  if (status == RunStatus::kCorrupt || status == RunStatus::kFailed) {
    fmt::print(stderr, "jam stats: warning: {} run {} left out: {}\n", to_string(status),
               visible(name), visible(detail));
  }
  if (status != RunStatus::kDone) {
    data.skipped.push_back(fmt::format("{} ({})", name, to_string(status)));
    return;
  }
  data.runs.push_back(read());
}

/// The runs through the campaign's manifest, in its plan order; nullopt when a run file
/// stores no fingerprint or another run's (the caller plans, and says what differs).
std::optional<CampaignData> read_manifest_runs(const std::string& directory, CampaignData data,
                                               const std::vector<ManifestRun>& runs) {
  for (const ManifestRun& run : runs) {
    std::string detail;
    const std::optional<RunStatus> status = manifest_run_status(directory, run, &detail);
    if (!status) return std::nullopt;
    const std::string file =
        (std::filesystem::path(directory) / "runs" / (run.name + ".h5")).string();
    take_run(data, run.name, *status, detail, [&] {
      return read_run_curves(file, run.n, run.phi_init, run.log10_rate, run.sample);
    });
  }
  return data;
}

}  // namespace

CampaignData read_campaign_runs(const std::string& directory) {
  if (is_external_campaign(directory)) return read_external_runs(directory);
  const Campaign campaign = stored_campaign(directory);
  CampaignData data;
  data.name = campaign.name;
  data.dim = campaign.run.dim;
  data.phi_step = campaign.run.phi_step;
  for (std::size_t k = 0; k < campaign.chain_phi_init.size(); ++k) {
    if (campaign.chain_phi_init[k] > 0.0) {
      data.chain_phi_init[campaign.log10_rates[k]] = campaign.chain_phi_init[k];
    }
  }
  // The plan the campaign ran with, as its manifest records it; planned again only for a
  // directory without a current manifest (restored from a snapshot, run by an older jam).
  if (const auto manifest = read_current_manifest(directory)) {
    if (auto read = read_manifest_runs(directory, data, *manifest)) return std::move(*read);
  }
  Campaign located = campaign;
  located.output = directory;  // the directory may have moved since it was run
  for (const PlannedRun& run : plan_runs(located)) {
    std::string detail;
    const RunStatus status = run_status(run, &detail);
    take_run(data, run.name, status, detail, [&] {
      return read_run_curves(run.config.out, run.n, run.phi_init, run.log10_rate, run.sample);
    });
  }
  return data;
}

Ensembles group_runs(const std::vector<RunCurves>& runs, bool pool_sizes) {
  Ensembles e;
  for (const RunCurves& r : runs) {
    auto& members = e[EnsembleKey{pool_sizes ? 0 : r.n, r.phi_init, r.log10_rate}];
    members.push_back(r);
    if (pool_sizes) members.back().sample = r.n * kPooledSampleStride + r.sample;
  }
  return e;
}

}  // namespace jam::stats
