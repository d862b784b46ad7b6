// libFuzzer target: an external campaign's record (external.toml) on arbitrary bytes. Any
// input must end in an ExternalCampaign or a std::runtime_error naming the file; nothing else
// may escape, the sanitizers stay silent, and a record that reads is written back by jam's own
// writer and read again to the same campaign (the reader accepts what the writer writes, and
// the writer loses nothing the reader took).
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "campaign/external_campaign.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path& scratch() {
  static const fs::path dir = [] {
    const fs::path d =
        fs::temp_directory_path() / ("jam-fuzz-external-" + std::to_string(::getpid()));
    fs::create_directories(d / "a");
    fs::create_directories(d / "b");
    return d;
  }();
  return dir;
}

bool same_number(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

void require_same(const jam::ExternalCampaign& x, const jam::ExternalCampaign& y) {
  bool same = x.name == y.name && same_number(x.phi_step, y.phi_step) && x.dim == y.dim &&
              same_number(x.diameter_ratio, y.diameter_ratio) && x.contact == y.contact &&
              x.dynamics == y.dynamics && same_number(x.quality_factor, y.quality_factor) &&
              x.runs.size() == y.runs.size() && x.set_aside.size() == y.set_aside.size();
  for (std::size_t k = 0; same && k < x.runs.size(); ++k) {
    const auto &a = x.runs[k], &b = y.runs[k];
    same = a.name == b.name && a.n == b.n && same_number(a.phi_init, b.phi_init) &&
           same_number(a.log10_rate, b.log10_rate) && a.sample == b.sample &&
           a.source == b.source && a.source_checksum == b.source_checksum &&
           a.simulator == b.simulator && a.simulator_version == b.simulator_version &&
           a.origin == b.origin;
  }
  if (!same) std::abort();  // the round trip changed the campaign: a finding
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path a = scratch() / "a", b = scratch() / "b";
  {
    std::ofstream out(a / "external.toml", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  jam::ExternalCampaign c;
  try {
    c = jam::read_external_campaign(a.string());
  } catch (const std::runtime_error&) {
    return 0;
  }
  fs::remove(b / "external.toml");
  jam::write_external_campaign(b.string(), c);
  require_same(c, jam::read_external_campaign(b.string()));
  return 0;
}
