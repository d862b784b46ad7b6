// The checksum walk (sim/io/content_checksum.cpp) refuses what jam never writes, before
// following it: a soft link and an external link (either could point anywhere, outside the
// file too), groups nested deeper than 32, and a virtual dataset (its values kept in other
// files). Each is planted with the HDF5 library into a sound run file written by jam; the
// run file is then corrupt, with a one-line reason naming the object. The cases that could
// hang or allocate without bound (a loop of links, external storage in a FIFO, unwritten
// chunks) are in test_hdf5_shapes.cpp.
#include <hdf5.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "hostile_hdf5.hpp"
#include "scratch.hpp"
#include "sim/io/run_file.hpp"

namespace fs = std::filesystem;
using jam::test::Editor;

namespace {

const jam::test::ScratchDir kDir("checksum-walk");

fs::path valid_run_file(const std::string& name) {
  return jam::test::valid_run_file(kDir.path(), name);
}

/// The run file's problem contains `text`, on one line.
void expect_corrupt(const fs::path& file, const std::string& text) {
  const std::string problem = jam::run_file_problem(file.string());
  BOOST_TEST(problem.find(text) != std::string::npos, problem);
  BOOST_TEST(problem.find('\n') == std::string::npos, problem);
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_soft_link_is_refused_not_followed) {
  const fs::path file = valid_run_file("soft.h5");
  {
    Editor e(file);
    BOOST_REQUIRE(H5Lcreate_soft("/pressure", e.id(), "again", H5P_DEFAULT, H5P_DEFAULT) >= 0);
  }
  expect_corrupt(file, "again: a soft or external link, not written by jam");
}

BOOST_AUTO_TEST_CASE(an_external_link_is_refused_not_followed) {
  const fs::path file = valid_run_file("external.h5");
  const fs::path other = valid_run_file("other.h5");
  {
    Editor e(file);
    BOOST_REQUIRE(H5Lcreate_external(other.c_str(), "/pressure", e.id(), "elsewhere", H5P_DEFAULT,
                                     H5P_DEFAULT) >= 0);
  }
  expect_corrupt(file, "elsewhere: a soft or external link, not written by jam");
}

BOOST_AUTO_TEST_CASE(groups_nested_deeper_than_32_are_refused) {
  for (const int depth : {31, 33}) {
    BOOST_TEST_CONTEXT("depth " << depth) {
      const fs::path file = valid_run_file("nested" + std::to_string(depth) + ".h5");
      {
        Editor e(file);
        hid_t parent = e.id();
        std::vector<hid_t> opened;
        for (int k = 0; k < depth; ++k) {
          opened.push_back(H5Gcreate2(parent, "g", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
          BOOST_REQUIRE(opened.back() >= 0);
          parent = opened.back();
        }
        for (auto it = opened.rbegin(); it != opened.rend(); ++it) H5Gclose(*it);
      }
      // The root is the walk's first level: 31 groups below it are 32 levels, 33 are 34.
      const std::string problem = jam::run_file_problem(file.string());
      if (depth == 31) {
        // Sound but for its checksum: the walk reached the bottom and hashed it.
        BOOST_TEST(problem.find("checksum") != std::string::npos, problem);
        BOOST_TEST(problem.find("nested") == std::string::npos, problem);
      } else {
        BOOST_TEST(
            problem.find("groups nested deeper than the file can be sound") != std::string::npos,
            problem);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(a_virtual_dataset_is_refused_not_read) {
  const fs::path file = valid_run_file("virtual.h5");
  const fs::path source = valid_run_file("source.h5");
  {
    Editor e(file);
    const hsize_t n = 5;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    BOOST_REQUIRE(H5Pset_virtual(dcpl, space, source.c_str(), "/pressure", space) >= 0);
    const hid_t d =
        H5Dcreate2(e.id(), "mapped", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    BOOST_REQUIRE(d >= 0);
    H5Dclose(d);
    H5Pclose(dcpl);
    H5Sclose(space);
  }
  expect_corrupt(file, "mapped: keeps its values in another file");
}
