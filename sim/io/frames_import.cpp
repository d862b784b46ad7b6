#include "sim/io/frames_import.hpp"

#include "sim/io/frames_import_of.hpp"

namespace jam {

void import_frames(const std::string& frames, const std::string& out) {
  import_frames_of<ContactLaws>(frames, out);
}

}  // namespace jam
