// libFuzzer target: the LAMMPS data-file reader (2D and 3D) on arbitrary bytes. Any input must
// end in a configuration or a std::runtime_error naming the file and line; nothing else may
// escape, and the sanitizers (ASan, UBSan) must stay silent. An accepted configuration must be
// in the box with a positive finite length.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/io/lammps_data.hpp"

namespace {

template <int D>
void read(const std::string& text) {
  std::istringstream in(text);
  try {
    const jam::LammpsData<D> data = jam::read_lammps_data<D>(in, "fuzz.data");
    if (!(data.box_length > 0.0 && std::isfinite(data.box_length))) std::abort();
    for (int d = 0; d < D; ++d) {
      for (double s : data.particles.s[d]) {
        if (!(s >= 0.0 && s < 1.0)) std::abort();
      }
    }
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind("fuzz.data:", 0) != 0) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  read<2>(text);
  read<3>(text);
  return 0;
}
