#include "stats/stats_inputs.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <vector>

#include "campaign/campaign_dir.hpp"
#include "campaign/external_campaign.hpp"
#include "campaign/run_plan.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/hdf5_file.hpp"

namespace jam::stats {
namespace fs = std::filesystem;
namespace {

/// What `jam stats DIR` reads: the lines its digest is taken of, and the files they come from
/// (for naming the one that changed).
struct Inputs {
  std::string text;
  std::vector<fs::path> files;
};

/// A run file's identity: its content checksum as the file states it ("absent" while there is
/// none; anything unreadable says so, and is then never equal to a checksum).
std::string run_identity(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return "absent";
  try {
    const h5::File f = h5::File::open_read(path);
    return f.has_attribute("checksum") ? f.read_attribute_string("checksum") : "no checksum";
  } catch (const std::exception& e) {
    return std::string("unreadable: ") + e.what();
  }
}

Inputs external_inputs(const fs::path& dir) {
  Inputs in;
  in.files.push_back(dir / "external.toml");
  const ExternalCampaign c = read_external_campaign(dir.string());
  in.text = fmt::format("external {} dim {} phi_step {:.17g}\n", c.name, c.dim, c.phi_step);
  for (const ExternalRun& r : c.runs) {
    in.text += fmt::format("run {} {}\n", r.name, r.source_checksum);
    in.files.push_back(dir / "runs" / (r.name + ".h5"));
  }
  return in;
}

Inputs planned_inputs(const fs::path& dir) {
  Inputs in;
  in.files.push_back(dir / "campaign.toml");
  Campaign c = stored_campaign(dir.string());
  c.output = dir.string();  // the directory may have moved since it was run
  in.files.emplace_back(added_samples_path(c));
  in.text = fmt::format("planned {} dim {} phi_step {:.17g}\n", c.name, c.run.dim, c.run.phi_step);
  for (std::size_t k = 0; k < c.chain_phi_init.size(); ++k)
    in.text += fmt::format("chain {:.17g} {:.17g}\n", c.log10_rates[k], c.chain_phi_init[k]);
  for (const PlannedRun& run : plan_runs(c)) {
    in.text += fmt::format("run {} {}\n", run.name, run_identity(run.config.out));
    in.files.emplace_back(run.config.out);
  }
  return in;
}

/// DIR's inputs; nullopt when there is nothing to compare stats.h5 with. A campaign file that
/// no longer reads is an input that changed: its error is its identity.
std::optional<Inputs> inputs_of(const fs::path& dir) {
  if (!fs::is_directory(dir / "runs")) return std::nullopt;
  const bool external = is_external_campaign(dir.string());
  if (!external && !fs::exists(dir / "campaign.toml")) return std::nullopt;
  try {
    return external ? external_inputs(dir) : planned_inputs(dir);
  } catch (const std::exception& e) {
    Inputs in;
    in.files.push_back(dir / (external ? "external.toml" : "campaign.toml"));
    in.text = std::string("unreadable: ") + e.what();
    return in;
  }
}

using Time = fs::file_time_type;

Time modified(const fs::path& p) {
  std::error_code ec;
  const Time t = fs::last_write_time(p, ec);
  return ec ? Time::min() : t;
}

/// The newest of `files` written after `than`; nullopt when none is.
std::optional<fs::path> newest_after(const std::vector<fs::path>& files, Time than) {
  std::optional<fs::path> newest;
  Time at = than;
  for (const fs::path& f : files) {
    if (const Time t = modified(f); t > at) {
      at = t;
      newest = f;
    }
  }
  return newest;
}

/// stats.h5's recorded digest ("" when it has none or cannot be read: the reader then says why
/// it cannot be read).
std::string recorded_checksum(const fs::path& stats) {
  try {
    const h5::File f = h5::File::open_read(stats.string());
    return f.has_attribute("inputs_checksum") ? f.read_attribute_string("inputs_checksum") : "";
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

void check_stats_checksum(const h5::File& f, const std::string& directory) {
  if (!f.has_attribute("checksum")) return;
  if (const std::string why = seal_problem(f); !why.empty())
    throw std::runtime_error(
        fmt::format("{}: {}: changed since `jam stats` wrote it; run `jam stats {}` again",
                    f.path(), why, directory));
}

std::string inputs_checksum(const std::string& directory) {
  const std::optional<Inputs> in = inputs_of(directory);
  return in ? checksum_text(bytes_checksum(in->text)) : std::string();
}

std::string stale_stats_reason(const std::string& directory) {
  const fs::path dir(directory), stats = dir / "stats.h5";
  if (!fs::exists(fs::symlink_status(stats))) return "";
  const std::optional<Inputs> in = inputs_of(dir);
  if (!in) return "";
  const std::optional<fs::path> newer = newest_after(in->files, modified(stats));
  const std::string recorded = recorded_checksum(stats);
  if (!recorded.empty()) {
    if (checksum_text(bytes_checksum(in->text)) == recorded) return "";
    if (newer) return fmt::format("{} is newer than it", newer->string());
    return fmt::format(
        "its runs are not those it was averaged from (inputs_checksum {} in the "
        "file, {} of {} now)",
        recorded, checksum_text(bytes_checksum(in->text)), dir.string());
  }
  // Written before stats.h5 recorded its inputs: their modification times.
  return newer ? fmt::format("{} is newer than it", newer->string()) : std::string();
}

}  // namespace jam::stats
