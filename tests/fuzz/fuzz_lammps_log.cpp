// libFuzzer target: the LAMMPS log reader (sim/io/lammps_log.hpp) on arbitrary text, with the
// columns of the bundled input and of the generic import, then the checks of its deforms and
// runs. Any input must end in a table or a std::runtime_error naming the log; nothing else may
// escape, and the sanitizers must stay silent. An accepted table has one value per row in every
// column, all finite, and a run holding them.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/io/lammps_log.hpp"

namespace {

void read(const std::string& text, const std::vector<std::string>& columns) {
  std::istringstream in(text);
  try {
    const jam::LammpsLog log = jam::read_lammps_log(in, "fuzz.log", columns);
    for (const auto& [name, values] : log.columns) {
      if (values.size() != log.lines.size()) std::abort();
      for (double v : values)
        if (!std::isfinite(v)) std::abort();
    }
    if (log.runs.empty()) std::abort();  // rows were read: they belong to a run
    // What the imports conclude from the log's deforms and runs (lammps_deform.hpp).
    jam::check_isotropic_deforms(log.deforms, log.dim.value_or(2), "fuzz.log");
    jam::check_packing_from_time(log.deforms, log.runs, log.lines.front(), "fuzz.log");
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind("fuzz.log", 0) != 0) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  read(text, {"Step", "Time", "c_virial", "PotEng", "v_Z"});
  read(text, {"c_virial", "Volume"});
  return 0;
}
