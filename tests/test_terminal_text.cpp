// Control characters of file names and values never reach the terminal: visible() writes them
// out, and jam's error lines, `jam validate` and the import lines go through it.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "process.hpp"
#include "sim/io/terminal_text.hpp"

namespace fs = std::filesystem;
using jam::visible;

BOOST_AUTO_TEST_CASE(plain_text_and_utf8_are_kept) {
  BOOST_TEST(visible("runs/n64_s001.h5") == "runs/n64_s001.h5");
  BOOST_TEST(visible("Δp/p ≥ 10% — ok 🙂") == "Δp/p ≥ 10% — ok 🙂");
}

BOOST_AUTO_TEST_CASE(c0_controls_and_del_are_written_out) {
  BOOST_TEST(visible("a\x1b[31mred") == "a\\x1b[31mred");
  BOOST_TEST(visible("one\nline\ttab\r\b") == "one\\x0aline\\x09tab\\x0d\\x08");
  BOOST_TEST(visible(std::string("nul\0x", 5)) == "nul\\x00x");
  BOOST_TEST(visible("del\x7f") == "del\\x7f");
}

BOOST_AUTO_TEST_CASE(c1_controls_and_invalid_utf8_are_written_out) {
  // U+009B (CSI) as UTF-8, a lone 0x9b (the 8-bit CSI), an overlong '/', a surrogate, a
  // truncated sequence at the end.
  BOOST_TEST(visible("\xc2\x9b"
                     "31m") == "\\u009b31m");
  BOOST_TEST(visible("\x9b"
                     "31m") == "\\x9b31m");
  BOOST_TEST(visible("\xc0\xaf") == "\\xc0\\xaf");
  BOOST_TEST(visible("\xed\xa0\x80") == "\\xed\\xa0\\x80");
  BOOST_TEST(visible("ok\xe2\x82") == "ok\\xe2\\x82");
}

BOOST_AUTO_TEST_CASE(jam_shows_control_characters_of_a_file_name) {
  const fs::path dir = fs::temp_directory_path() / ("jam-terminal-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path run = dir / "run\x1b]0;owned\x07\x1b[2J.h5";
  std::ofstream(run) << "not HDF5";
  const auto o = jam::test::run_logged(dir / "log.txt", {JAM_EXECUTABLE, "validate", run.string()});
  BOOST_TEST(o.status == 1);
  BOOST_TEST(o.output.find('\x1b') == std::string::npos);
  BOOST_TEST(o.output.find("run\\x1b]0;owned\\x07\\x1b[2J.h5") != std::string::npos);
  // An error of any subcommand: a campaign directory that does not exist.
  const fs::path missing = dir / "gone\x1b[8m";
  const auto e = jam::test::run_logged(dir / "log2.txt",
                                       {JAM_EXECUTABLE, "campaign", "status", missing.string()});
  BOOST_TEST(e.status == 2);
  BOOST_TEST(e.output.find('\x1b') == std::string::npos);
  BOOST_TEST(e.output.find("gone\\x1b[8m") != std::string::npos);
  fs::remove_all(dir);
}
