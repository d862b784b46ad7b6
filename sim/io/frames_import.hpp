#pragma once
// `jam import frames`: configurations of another simulator (a GSD trajectory without a logged
// pressure, converted by jamio.gsd_import) measured with jam's own observables. The frames file
// (docs/cross-simulator.md, "Configuration frames") carries the open run's attributes and, per
// frame, the box length and the positions; the diameters once. jam checks that the diameters are
// the model's (N/2 of 1, N/2 of diameter_ratio), derives phi from L, and writes an open run with
// p, Z and the energy per particle measured by sim/observables for the contact law named. A
// frame whose box is not above twice the interaction range (jam sim's rule,
// minimum_image_box_length) is refused: there a pair can touch through two images.
#include <string>

namespace jam {

/// Reads and checks `frames`, measures every frame, writes the open run to `out` atomically.
/// Throws std::runtime_error naming the file, the field and the value.
void import_frames(const std::string& frames, const std::string& out);

}  // namespace jam
