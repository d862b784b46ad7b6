#include "sim/io/terminal_text.hpp"

#include <fmt/format.h>

namespace jam {
namespace {

/// The length of the valid UTF-8 sequence starting at text[k] (2 to 4 bytes), or 0.
std::size_t utf8_length(std::string_view text, std::size_t k) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(k);
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte (RFC 3629, table 3-7)
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;  // no surrogates
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (k + length > text.size()) return 0;
  if (byte(k + 1) < low || byte(k + 1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i)
    if (byte(k + i) < 0x80 || byte(k + i) > 0xBF) return 0;
  return length;
}

}  // namespace

std::string visible(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size();) {
    const auto c = static_cast<unsigned char>(text[k]);
    if (c < 0x20 || c == 0x7F) {
      out += fmt::format("\\x{:02x}", c);
      ++k;
    } else if (c < 0x80) {
      out += static_cast<char>(c);
      ++k;
    } else if (const std::size_t n = utf8_length(text, k); n == 0) {
      out += fmt::format("\\x{:02x}", c);
      ++k;
    } else if (c == 0xC2 && static_cast<unsigned char>(text[k + 1]) <= 0x9F) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(text[k + 1]));  // a C1 control
      k += 2;
    } else {
      out.append(text.substr(k, n));
      k += n;
    }
  }
  return out;
}

}  // namespace jam
