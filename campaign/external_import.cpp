// `jam campaign import DIR FILE...` (campaign/external_campaign.hpp): how runs join.
//
// Every file is read, checked and checksummed first, before the directory is touched, so an
// import of which nothing can be read writes nothing. Then the import takes the campaign's lock
// (campaign_lock.hpp; imports wait for each other), reads external.toml afresh under it, adds
// to it and writes it back through a temporary: two imports at once both land. A new campaign's
// external.toml is written first, with no runs, so an import killed after that leaves an
// external campaign that the next import (the same one again, say) completes. Each run is
// copied to a temporary in runs/ and renamed to its name only when nothing is there
// (import_store.hpp): a file there that external.toml does not list is never replaced nor
// written through; it is adopted only when its checksum is that of the file being imported (a
// copy an interrupted import made), and otherwise set aside by name.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "campaign/campaign_dir.hpp"
#include "campaign/campaign_lock.hpp"
#include "campaign/external_campaign.hpp"
#include "campaign/grid_limit.hpp"
#include "campaign/import_store.hpp"
#include "campaign/run_plan.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/output_path.hpp"

namespace fs = std::filesystem;

namespace jam {
namespace {

/// A file given to import, as read before the campaign is touched.
struct Candidate {
  std::string file;
  OpenRun run;                    // its datasets dropped: the attributes decide where it goes
  std::string checksum, problem;  // problem: why it cannot be imported ("" when it can)
  bool sample_given = true;       // false: a run file of jam's own without a `sample`
};

Candidate read_candidate(const std::string& file) {
  Candidate k{file, {}, "", "", true};
  try {
    // Checksummed before and after it is read: the bytes copied later are compared with this
    // checksum, so they are the bytes that were checked.
    k.checksum = file_checksum(file);
    k.run = read_open_run(file);
    if (file_checksum(file) != k.checksum) throw std::runtime_error(file + ": changed while read");
    if (k.run.jam_native) k.sample_given = h5::File::open_read(file).has_attribute("sample");
    k.run.packing_fraction = k.run.pressure = k.run.contacts_per_particle = {};
    k.run.energy_per_particle = k.run.time = {};
  } catch (const std::exception& e) {
    k.problem = e.what();
  }
  return k;
}

/// A campaign name names the report's directory: one plain word, never a path.
void check_name(const std::string& name) {
  if (!is_plain_campaign_name(name))
    throw std::runtime_error(fmt::format(
        "--name '{}': must be one word of letters, digits and . _ + - that begins with a letter, "
        "digit or _ (it names the report's directory)",
        name));
}

/// The directory's name as a campaign name: what check_name refuses made plain.
std::string default_name(const fs::path& d) {
  std::string name = fs::absolute(d).lexically_normal().filename().string();
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && !std::strchr("._+-", ch)) ch = '_';
  name.erase(0, name.find_first_not_of(".+-"));
  return name.empty() ? "external" : name.substr(0, 255);
}

/// Why `step` cannot be a campaign's grid ("" when it can): stats refuses a grid beyond its
/// limit (campaign/grid_limit.hpp), and a grid of step s over packings in (0, 1) has 1/s points.
std::string phi_step_problem(double step) {
  if (!(step > 0 && step <= 0.05))
    return fmt::format("--phi-step {:g}: must be in (0, 0.05]", step);
  if (!(1.0 / step <= kMaxGridPoints))
    return fmt::format(
        "--phi-step {:g}: a grid of up to {:.3g} points over packings in (0, 1), more than the "
        "statistics' limit of {:g} (the step must be at least {:g})",
        step, 1.0 / step, kMaxGridPoints, 1.0 / kMaxGridPoints);
  return "";
}

enum class Found { kExternal, kFresh };

/// What `d` holds: an external campaign, or nothing yet (absent; empty; or what an interrupted
/// first import of an older jam left: runs/ holding run files only). Anything else is refused.
Found inspect(const fs::path& d) {
  std::error_code ec;
  const auto runs = fs::symlink_status(d / "runs", ec).type();
  if (runs != fs::file_type::not_found && runs != fs::file_type::directory)
    throw std::runtime_error(fmt::format(
        "{}: not a directory of its own (a link or another file); an external campaign keeps its "
        "runs there",
        (d / "runs").string()));
  if (is_external_campaign(d.string())) return Found::kExternal;
  if (fs::exists(d / "campaign.toml") || fs::exists(d / "manifest.toml"))
    throw std::runtime_error(fmt::format(
        "{}: a planned campaign (campaign.toml); import into a directory of its own", d.string()));
  auto refuse = [&] {
    throw std::runtime_error(fmt::format(
        "{}: not empty and not an external campaign; import into a new directory", d.string()));
  };
  if (!fs::exists(d)) return Found::kFresh;
  for (const auto& e : fs::directory_iterator(d)) {
    const std::string name = e.path().filename().string();
    if (name == ".lock" && e.symlink_status().type() == fs::file_type::regular) continue;
    if (name != "runs") refuse();
    for (const auto& r : fs::directory_iterator(e.path()))
      if (r.symlink_status().type() != fs::file_type::regular) refuse();
  }
  return Found::kFresh;
}

/// Why r cannot join campaign c ("" when it can).
std::string model_mismatch(const ExternalCampaign& c, const OpenRun& r) {
  if (r.dim != c.dim) return fmt::format("dim {}, the campaign's {}", r.dim, c.dim);
  if (std::abs(r.diameter_ratio - c.diameter_ratio) > 1e-12)
    return fmt::format("diameter_ratio {}, the campaign's {}", r.diameter_ratio, c.diameter_ratio);
  if (r.contact != c.contact)
    return fmt::format("contact {}, the campaign's {}", r.contact, c.contact);
  if (r.dynamics != c.dynamics || std::abs(r.quality_factor - c.quality_factor) > 1e-12)
    return fmt::format("dynamics {} (Q {}), the campaign's {} (Q {})", r.dynamics, r.quality_factor,
                       c.dynamics, c.quality_factor);
  return "";
}

/// The campaign to add to, under the lock: external.toml read afresh, or a new one (its model
/// the first readable file's) whose external.toml is written before any run is copied.
ExternalCampaign open_campaign(const fs::path& d, const ImportOptions& o,
                               const std::vector<Candidate>& files,
                               std::vector<std::string>& notes) {
  if (inspect(d) == Found::kExternal) {
    ExternalCampaign c = read_external_campaign(d.string());
    if (o.phi_step && std::abs(*o.phi_step - c.phi_step) > 1e-15) {
      // A step the statistics refuse (recorded by an older jam) may be replaced; another not.
      if (phi_step_problem(c.phi_step).empty())
        throw std::runtime_error(
            fmt::format("--phi-step {}: the campaign's is {}", *o.phi_step, c.phi_step));
      notes.push_back(fmt::format("{}: phi_step {:g} (beyond the statistics' limit) is now {:g}",
                                  d.string(), c.phi_step, *o.phi_step));
      c.phi_step = *o.phi_step;
    }
    fs::create_directories(d / "runs");
    return c;
  }
  const auto first = std::find_if(files.begin(), files.end(),
                                  [](const Candidate& k) { return k.problem.empty(); });
  if (first == files.end())
    throw std::runtime_error(
        fmt::format("{}: no file can be imported; nothing written", d.string()));
  ExternalCampaign c;
  c.name = o.name.empty() ? default_name(d) : o.name;
  c.phi_step = o.phi_step.value_or(0.0005);
  const OpenRun& r = first->run;
  c.dim = r.dim, c.diameter_ratio = r.diameter_ratio, c.contact = r.contact;
  c.dynamics = r.dynamics, c.quality_factor = r.quality_factor;
  fs::create_directories(d / "runs");
  write_external_campaign(d.string(), c);
  return c;
}

fs::path stored_path(const fs::path& d, const std::string& name) {
  return d / "runs" / (name + ".h5");
}

/// What is wrong with the stored copy of a listed run ("" when it is as imported).
std::string stored_copy_damage(const fs::path& path, const std::string& checksum) {
  std::error_code ec;
  const auto type = fs::symlink_status(path, ec).type();
  if (type == fs::file_type::not_found) return "missing";
  if (type != fs::file_type::regular) return "no longer a regular file";
  try {
    return file_checksum(path.string()) == checksum
               ? ""
               : "changed since it was imported (its checksum differs)";
  } catch (const std::exception& e) {
    return e.what();
  }
}

/// The whole import of one file into c; outcomes go to out.
class Importer {
 public:
  Importer(fs::path d, ExternalCampaign& c, ImportOutcome& out)
      : d_(std::move(d)), c_(c), out_(out) {}

  void add(const Candidate& k) {
    if (!k.problem.empty()) return aside(k.file, k.problem);
    if (const std::string why = model_mismatch(c_, k.run); !why.empty()) return aside(k.file, why);
    ExternalRun x{"",
                  k.run.n,
                  k.run.sample,
                  k.run.phi_init,
                  std::log10(k.run.compression_rate),
                  fs::absolute(k.file).lexically_normal().string(),
                  k.checksum,
                  k.run.simulator,
                  k.run.simulator_version,
                  k.run.source};
    // Its ensemble: the first run's nominal phi_init and rate, within what a run name tells.
    for (const auto& e : c_.runs)
      if (e.n == x.n && std::abs(e.phi_init - x.phi_init) <= 1e-6 &&
          std::abs(e.log10_rate - x.log10_rate) <= 1e-9) {
        x.phi_init = e.phi_init, x.log10_rate = e.log10_rate;
        break;
      }
    if (!k.sample_given) x.sample = sample_for(x, k.checksum);
    x.name = run_name(x.n, x.phi_init, x.log10_rate, x.sample);
    const auto listed = std::find_if(c_.runs.begin(), c_.runs.end(),
                                     [&](const ExternalRun& e) { return e.name == x.name; });
    if (listed != c_.runs.end()) return again(*listed, k);
    if (store(x, k) && !k.sample_given)
      out_.notes.push_back(fmt::format(
          "{}: a run file of jam's own without a sample id: imported as sample {} of its "
          "ensemble ({})",
          k.file, x.sample, stored_path(d_, x.name).string()));
  }

 private:
  void aside(const std::string& file, const std::string& reason) {
    out_.set_aside.push_back({file, reason});
    c_.set_aside.push_back({file, reason});
  }

  /// The sample id of a file without one (`jam sim` writes none; the file's checksum covers
  /// its attributes, and external.toml, not the file, carries a run's sample): the id it was
  /// imported under before, or the first free one of its ensemble. A free id whose file is
  /// already in runs/ unlisted is passed over, unless that file is this one's copy.
  std::int64_t sample_for(const ExternalRun& x, const std::string& checksum) const {
    for (std::int64_t s = 0;; ++s) {
      const std::string name = run_name(x.n, x.phi_init, x.log10_rate, s);
      const auto listed = std::find_if(c_.runs.begin(), c_.runs.end(),
                                       [&](const ExternalRun& e) { return e.name == name; });
      if (listed != c_.runs.end()) {
        if (listed->source_checksum == checksum) return s;
        continue;
      }
      const fs::path there = stored_path(d_, name);
      std::error_code ec;
      if (fs::symlink_status(there, ec).type() == fs::file_type::not_found ||
          stored_copy_damage(there, checksum).empty())
        return s;
    }
  }

  /// A file whose run is listed: already there, its damaged copy repaired, or set aside.
  void again(const ExternalRun& listed, const Candidate& k) {
    const fs::path path = stored_path(d_, listed.name);
    const std::string damage = stored_copy_damage(path, listed.source_checksum);
    if (listed.source_checksum != k.checksum) {
      return aside(
          k.file,
          fmt::format(
              "sample {} of n {}, phi_init {:g}, rate 1e{:g} is already imported (from {}); "
              "give it another sample id{}",
              listed.sample, listed.n, listed.phi_init, listed.log10_rate, listed.source,
              damage.empty() ? ""
                             : fmt::format("; and the stored copy {} is damaged ({}): "
                                           "import {} again to repair it",
                                           path.string(), damage, listed.source)));
    }
    if (damage.empty()) {
      ++out_.already;
      return;
    }
    // The file is the one imported (its checksum is the recorded one): the copy is ours to
    // replace; the rename replaces a link put there, never the file it points to.
    Temporary copy(copy_to_temporary(k.file, path.string()));
    if (file_checksum(copy.path()) != listed.source_checksum)
      return aside(k.file, "changed while it was imported; import it again");
    if (std::rename(copy.path().c_str(), path.c_str()) != 0)
      throw WriteError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
    copy.release();
    ++out_.repaired;
    out_.notes.push_back(
        fmt::format("{}: was {}; repaired from {}, whose checksum is the one "
                    "recorded",
                    path.string(), damage, k.file));
  }

  /// Copies a new run to runs/ and lists it; true when it joined.
  bool store(const ExternalRun& x, const Candidate& k) {
    const fs::path path = stored_path(d_, x.name);
    std::error_code ec;
    if (fs::symlink_status(path, ec).type() != fs::file_type::not_found) {
      if (!stored_copy_damage(path, k.checksum).empty()) return unlisted(path, k);
      out_.notes.push_back(fmt::format(
          "{}: adopted: not listed (an import was interrupted), and its checksum is {}'s",
          path.string(), k.file));
    } else {
      Temporary copy(copy_to_temporary(k.file, path.string()));
      if (file_checksum(copy.path()) != k.checksum) {
        aside(k.file, "changed while it was imported; import it again");
        return false;
      }
      const int error = rename_no_replace(copy.path(), path.string());
      if (error == EEXIST) return unlisted(path, k);
      if (error != 0)
        throw WriteError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(error)));
      copy.release();
    }
    c_.runs.push_back(x);
    ++out_.imported;
    return true;
  }

  bool unlisted(const fs::path& path, const Candidate& k) {
    aside(k.file, fmt::format("{} is there and external.toml does not list it: left as it is "
                              "(move it away, then import again)",
                              path.string()));
    return false;
  }

  fs::path d_;
  ExternalCampaign& c_;
  ImportOutcome& out_;
};

}  // namespace

ImportOutcome import_runs(const std::string& directory, const std::vector<std::string>& files,
                          const ImportOptions& options) {
  const fs::path d(directory);
  check_output_directory("directory", directory);
  if (!options.name.empty()) check_name(options.name);
  if (options.phi_step)
    if (const std::string why = phi_step_problem(*options.phi_step); !why.empty())
      throw std::runtime_error(why);
  std::vector<Candidate> read;
  for (const std::string& file : files) read.push_back(read_candidate(file));
  // Refused before anything is written: a directory not to import into, or nothing to import
  // into a new campaign.
  if (inspect(d) == Found::kFresh &&
      std::none_of(read.begin(), read.end(), [](const Candidate& k) { return k.problem.empty(); }))
    throw std::runtime_error(fmt::format(
        "{}: {}, so nothing was written; {}", directory,
        read.size() == 1 ? "the file given cannot be imported"
                         : fmt::format("none of the {} files can be imported", read.size()),
        read.empty() ? "no file given" : "the first: " + read[0].problem));
  fs::create_directories(d);
  const CampaignLock lock(directory, "", /*wait=*/true);
  remove_stale_temporaries(directory);  // those of imports killed while they wrote
  ImportOutcome out;
  ExternalCampaign c = open_campaign(d, options, read, out.notes);
  Importer importer(d, c, out);
  try {
    for (const Candidate& k : read) importer.add(k);
  } catch (...) {
    // What was copied is listed, so a failed write (a full disk) loses nothing already done.
    try {
      write_external_campaign(directory, c);
    } catch (...) {
    }
    throw;
  }
  write_external_campaign(directory, c);
  return out;
}

}  // namespace jam
