#pragma once
// The text of a campaign's progress lines: a time span as a person reads it, and the UTC
// stamp that dates a line in a batch log (a day-long Slurm log shows how far it got).
#include <fmt/format.h>

#include <ctime>
#include <string>

namespace jam {

/// Seconds, minutes, hours or days, whichever reads best.
inline std::string duration_text(double seconds) {
  if (seconds < 120) return fmt::format("{:.0f} s", seconds);
  if (seconds < 7200) return fmt::format("{:.1f} min", seconds / 60);
  if (seconds < 172800) return fmt::format("{:.1f} h", seconds / 3600);
  return fmt::format("{:.1f} days", seconds / 86400);
}

/// Now, UTC, to the second.
inline std::string utc_time() {
  const std::time_t t = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

}  // namespace jam
