// A test-only jam with one more contact law, compiled into this executable alone: it shows that
// the open run format's validation, `jam import frames` and the schema jamio reads follow the
// list of laws with no edit beyond the list (tests/test_open_run_schema.py).
//
//   open_run_registry_tool schema              the schema of the longer list (TOML)
//   open_run_registry_tool validate RUN        `jam validate` with the longer list
//   open_run_registry_tool import FRAMES OUT   `jam import frames` with the longer list
#include <fmt/format.h>

#include <exception>
#include <string>
#include <tuple>

#include "sim/io/frames_import_of.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/open_run_schema.hpp"
#include "sim/model/contact_laws.hpp"

namespace {

// The Hertzian law under another name: what a new law's header would add (contact_law.hpp).
// Its pressure must equal the Hertzian one, which shows the dispatch reached it.
struct TestOnlyContact : jam::HertzianContact {
  static constexpr const char* kName = "test-only";
  static constexpr const char* kFormula = "U = (2/5)(1 - r/d)^(5/2) for r < d (test only)";
  using HertzianContact::HertzianContact;
};
static_assert(jam::ContactLaw<TestOnlyContact>);

// The registry with one more line.
using TestLaws = std::tuple<jam::HarmonicContact, jam::HertzianContact, TestOnlyContact>;

}  // namespace

int main(int argc, char** argv) {
  const std::string what = argc > 1 ? argv[1] : "";
  try {
    const jam::OpenRunSchema schema = jam::open_run_schema_of<TestLaws>();
    if (what == "schema" && argc == 2) {
      fmt::print("{}", jam::open_run_schema_toml(schema));
    } else if (what == "validate" && argc == 3) {
      const jam::OpenRun r = jam::read_open_run(argv[2], schema);
      fmt::print("{}: ok: contact {}\n", argv[2], r.contact);
    } else if (what == "import" && argc == 4) {
      jam::import_frames_of<TestLaws>(argv[2], argv[3]);
    } else {
      fmt::print(stderr,
                 "usage: open_run_registry_tool schema | validate RUN | import FRAMES OUT\n");
      return 2;
    }
  } catch (const std::exception& e) {
    fmt::print("{}\n", e.what());
    return 1;
  }
  return 0;
}
