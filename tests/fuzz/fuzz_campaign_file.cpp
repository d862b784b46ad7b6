// libFuzzer target: the campaign-file reader (TOML parse, keys, types, validation) on arbitrary
// bytes. Any input must end in a Campaign or a CampaignError; nothing else may escape, and the
// sanitizers (ASan, UBSan) must stay silent.
#include <cstddef>
#include <cstdint>
#include <string>

#include "campaign/campaign_file.hpp"
#include "campaign/run_plan.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const jam::Campaign c = jam::parse_campaign(text, "fuzz.toml");
    // A campaign that parses must also plan, unless it is too large to plan here.
    if (c.sizes.size() * c.phi_init.size() * c.log10_rates.size() *
            static_cast<std::size_t>(c.samples) <=
        10000) {
      jam::plan_runs(c);
    }
  } catch (const jam::CampaignError&) {
  }
  return 0;
}
