// The TOML files jam writes and reads back besides campaign files (run records, manifests,
// added-samples.toml, external.toml; campaign/toml_file.hpp): written in plain ASCII whatever
// they hold, read as outside input: a FIFO, an oversized file or raw non-ASCII text (on which
// Debian 12's toml++ 3.3.0 can reach undefined behaviour) is one error naming the file, never
// a hang or a parse.
#include <sys/stat.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "campaign/toml_file.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("jam_test_toml_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// The message of the error read_toml_file throws on `path` ("" if it reads).
std::string refusal(const fs::path& path) {
  try {
    jam::read_toml_file("test file", path.string());
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

BOOST_AUTO_TEST_CASE(what_jam_writes_is_ascii_and_reads_back) {
  // A user's path and an error message may hold any character; the text escapes them.
  const std::string path = "/home/user/donn\u00e9es/\u03c6 0.84/run.h5", error = "tab\there";
  const std::string text = jam::toml_text(toml::table{{"source", path}, {"error", error}});
  BOOST_TEST(!jam::first_non_ascii(text).has_value(), text);
  const fs::path file = scratch("ascii") / "f.toml";
  std::ofstream(file) << text;
  const toml::table back = jam::read_toml_file("test file", file.string());
  BOOST_TEST(back["source"].value_or(std::string()) == path);
  BOOST_TEST(back["error"].value_or(std::string()) == error);
}

BOOST_AUTO_TEST_CASE(raw_non_ascii_special_and_oversized_files_are_refused) {
  const fs::path d = scratch("refused");
  std::ofstream(d / "utf8.toml") << "a = 1\nb = 'donn\u00e9es'\n";
  BOOST_TEST(refusal(d / "utf8.toml") ==
             (d / "utf8.toml").string() + ":2: byte 0xc3: not plain ASCII text");
  std::ofstream(d / "control.toml") << "a = 1\n\nb = 2\x01\n";
  BOOST_TEST(refusal(d / "control.toml").find(":3: byte 0x01") != std::string::npos);
  std::ofstream(d / "bad.toml") << "a = 1\nb = = 2\n";
  BOOST_TEST(refusal(d / "bad.toml").rfind((d / "bad.toml").string() + ":2: ", 0) == 0,
             refusal(d / "bad.toml"));
  // A FIFO would block the read until a writer came: refused by its type, at once.
  BOOST_TEST_REQUIRE(::mkfifo((d / "fifo.toml").c_str(), 0600) == 0);
  BOOST_TEST(refusal(d / "fifo.toml").find("FIFO") != std::string::npos, refusal(d / "fifo.toml"));
  // Beyond the bound, by its size alone (a sparse file: nothing is read).
  { std::ofstream(d / "huge.toml") << "a = 1\n"; }
  fs::resize_file(d / "huge.toml", jam::kMaxTomlBytes + 1);
  BOOST_TEST(refusal(d / "huge.toml").find("bytes (at most") != std::string::npos,
             refusal(d / "huge.toml"));
  std::ofstream(d / "good.toml") << "a = 1\n";
  BOOST_TEST(refusal(d / "good.toml") == "");
  fs::remove_all(d);
}
