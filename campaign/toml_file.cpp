#include "campaign/toml_file.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "sim/io/output_path.hpp"

namespace jam {

std::optional<NonAsciiByte> first_non_ascii(std::string_view text) {
  int line = 1;
  for (const char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte == '\n') ++line;
    if (byte >= 0x80 || (byte < 0x20 && byte != '\n' && byte != '\t' && byte != '\r') ||
        byte == 0x7f)
      return NonAsciiByte{line, byte};
  }
  return std::nullopt;
}

std::optional<double> toml_number(const toml::node* node) {
  if (!node) return std::nullopt;
  if (const auto* f = node->as_floating_point()) return f->get();
  if (const auto* i = node->as_integer()) return static_cast<double>(i->get());
  return std::nullopt;
}

std::string toml_text(const toml::table& table) {
  std::ostringstream text;
  text << toml::toml_formatter{
      table, toml::toml_formatter::default_flags & ~toml::format_flags::allow_unicode_strings};
  return text.str();
}

toml::table read_toml_file(const std::string& what, const std::string& path) {
  check_input_file(what, path);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error(fmt::format("{}: cannot read: {}", path, ec.message()));
  if (bytes > kMaxTomlBytes)
    throw std::runtime_error(fmt::format("{}: {} bytes (at most {})", path, bytes, kMaxTomlBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read", path));
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (const auto bad = first_non_ascii(text))
    throw std::runtime_error(
        fmt::format("{}:{}: byte 0x{:02x}: not plain ASCII text", path, bad->line, bad->byte));
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(
        fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
  }
}

}  // namespace jam
