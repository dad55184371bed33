// SPDX-License-Identifier: BSD-2-Clause
// `svc bench`: the benchmark suite of bench/svc_bench.h as a subcommand of the svc tool.
// Built only with SVC_BUILD_BENCH (the tool then defines SVC_WITH_BENCH).
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

namespace svc::cli {

class BenchSubcommand {
 public:
  // Registers `bench` and its options on `app`; the object must outlive parsing.
  explicit BenchSubcommand(CLI::App& app);
  ~BenchSubcommand();
  bool parsed() const;
  // Runs the benchmark with the parsed options; returns the process exit status.
  int run() const;

 private:
  struct Options;
  std::unique_ptr<Options> options_;
  CLI::App* command_ = nullptr;
};

}  // namespace svc::cli
