#pragma once
// The TOML files jam reads besides a campaign file: run records, added-samples.toml and an
// external campaign's external.toml. jam writes them, but a user may edit or damage them, so
// each is read as outside input: a regular file only (no FIFO that would hang the read), of
// bounded size, plain ASCII (the TOML parser of Debian 12, toml++ 3.3.0, reaches undefined
// behaviour on some non-ASCII characters: marzer/tomlplusplus#295, found in jam by fuzzing the
// campaign reader), then parsed.
#include <toml++/toml.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace jam {

/// Where a text first leaves plain ASCII text (printable characters, tab, CR, LF).
struct NonAsciiByte {
  int line = 0;
  unsigned char byte = 0;
};
std::optional<NonAsciiByte> first_non_ascii(std::string_view text);

/// The largest TOML file read: a bound against a damaged or substituted file, far above what jam
/// writes (a record is a few hundred bytes; external.toml grows by one short table per run).
inline constexpr std::size_t kMaxTomlBytes = std::size_t{64} << 20;

/// `table` as TOML text in plain ASCII: characters beyond it (a user's path, an error message)
/// are written as \uXXXX escapes, so that read_toml_file reads back whatever jam wrote.
std::string toml_text(const toml::table& table);

/// A TOML number as a double: a float as it is, an integer rounded to the nearest double.
/// (toml++'s value<double>() is empty for an integer beyond 2^53 in magnitude, one that no
/// double holds exactly: found by fuzzing the campaign reader.) Empty when `node` is absent or
/// not a number.
std::optional<double> toml_number(const toml::node* node);

/// `path` parsed, or std::runtime_error "<path>[:line]: <cause>" (`what` names the kind of
/// file in the message about a special file).
toml::table read_toml_file(const std::string& what, const std::string& path);

}  // namespace jam
