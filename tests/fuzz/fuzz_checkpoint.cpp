// libFuzzer target: the checkpoint and relaxed-start reader (read_checkpoint, 2D and 3D) on
// arbitrary bytes. Any input must end in a checkpoint or in CorruptCheckpoint / ForeignCheckpoint;
// nothing else may escape, and the sanitizers must stay silent. The whole-file seal is checked
// before the HDF5 library parses anything (sealed_file.hpp), so damaged bytes never reach it.
// An accepted checkpoint must hold positions in the box.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "sim/io/checkpoint.hpp"
#include "sim/run/sim_config.hpp"

namespace {

const std::string kPath = "/tmp/jam-fuzz-checkpoint-" + std::to_string(::getpid()) + ".h5";

// The runs whose checkpoints and starts seed the corpus (corpus/checkpoint/): N = 8, stopped at
// the first checkpoint. Their fingerprints let sound inputs reach the data reader.
jam::SimConfig corpus_run(int dim) {
  jam::SimConfig c;
  c.dim = dim;
  c.n = 8;
  c.phi_init = dim == 2 ? 0.1 : 0.02;
  c.phi_stop = dim == 2 ? 0.15 : 0.03;
  c.phi_step = 0.01;
  c.compression_rate = 1e-3;
  c.relax_energy = "1e-30";
  return c;
}

template <int D>
void read(const std::string& fingerprint) {
  try {
    const auto c = jam::read_checkpoint<D>(kPath, fingerprint);
    if (!c) return;
    for (int d = 0; d < D; ++d) {
      for (double s : c->particles.s[d]) {
        if (!(s >= 0.0 && s < 1.0)) std::abort();
      }
    }
  } catch (const jam::CorruptCheckpoint&) {
  } catch (const jam::ForeignCheckpoint&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(kPath, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  for (const auto& c : {corpus_run(2), corpus_run(3)}) {
    for (const auto& fingerprint : {jam::fingerprint(c), jam::relaxation_fingerprint(c)}) {
      if (c.dim == 2) read<2>(fingerprint);
      if (c.dim == 3) read<3>(fingerprint);
    }
  }
  std::remove(kPath.c_str());
  return 0;
}
