#pragma once
// Small helpers shared by the benchmarks: where the machine and the command are noted, atomic
// text files, and the plot script.
#include <string>

namespace jam::bench {

/// "AMD EPYC ... , 2 cores" from /proc/cpuinfo.
std::string machine_description();

/// Current UTC date and time, ISO 8601.
std::string utc_now();

/// Writes text to path atomically (temporary name, then rename).
void write_text_file(const std::string& path, const std::string& text);

/// Runs bench/plot_benchmarks.py (with /usr/bin/python3 and matplotlib) on a CSV file of the
/// given kind ("throughput" or "accuracy") into png; returns false (and says why on stderr)
/// when the plot cannot be made: the tables are the result, the plot is a view of them.
bool plot(const std::string& kind, const std::string& csv, const std::string& png);

}  // namespace jam::bench
