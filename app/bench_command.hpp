#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "bench/accuracy.hpp"
#include "bench/throughput.hpp"

namespace jam {

struct BenchArgs {
  bench::ThroughputOptions throughput;
  bench::AccuracyOptions accuracy;
  std::string dims = "2,3";
};

/// Registers `jam bench throughput` and `jam bench accuracy`.
void add_bench_command(CLI::App& app, BenchArgs& args);

int run_bench_command(const CLI::App& app, BenchArgs& args, int argc, char** argv);

}  // namespace jam
