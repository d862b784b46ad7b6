#pragma once
// Where jam's own files are (reference data, report and plot scripts): an installed jam
// (`cmake --install`) finds them under <prefix>/share/jam/, next to its own location
// (<prefix>/bin/jam), so it keeps working with the source tree gone; a jam run from its build
// tree uses the source tree it was built from.
#include <filesystem>
#include <string>

namespace jam {

/// The directory of the running executable (from /proc/self/exe).
std::filesystem::path executable_directory();

/// <exe>/../share/jam/<relative> when it exists, else <source tree>/<relative>.
std::filesystem::path data_path(const std::string& relative);

}  // namespace jam
