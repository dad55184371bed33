// SPDX-License-Identifier: BSD-2-Clause
// svc-checkkernels: every variant of every pixel kernel this machine supports, of the
// shared table and of the encoder's, compared bit for bit with the plain reference on seeded random inputs and edge
// cases (in the spirit of dav1d's checkasm). --bench times each variant beside its reference.
//
//   svc-checkkernels [--seed N] [--iterations N] [--kernel NAME] [--bench]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

using codec::dsp::kCpuAvx2;
using codec::dsp::kCpuNeon;
using codec::dsp::kCpuSse2;
using codec::dsp::kCpuSse41;

struct Variant {
  const char* name;
  Tables tables;
};

// The plain table, then one table per feature level this machine has (the x86 levels or
// NEON); a kernel's variant at a level is the entry that differs from the level below.
std::vector<Variant> variants_of_this_machine() {
  const unsigned detected = codec::dsp::detected_cpu_flags();
  auto tables_for = [](unsigned flags) {
    return Tables{{codec::dsp::make_dsp_table(flags)},
                  {codec::dsp::make_encoder_dsp_table(flags)},
                  make_flow_kernels(flags)};
  };
  std::vector<Variant> variants = {{"c", tables_for(0)}};
  const struct {
    const char* name;
    unsigned flags;
  } levels[] = {{"sse2", kCpuSse2},
                {"sse4.1", kCpuSse2 | kCpuSse41},
                {"avx2", kCpuSse2 | kCpuSse41 | kCpuAvx2},
                {"neon", kCpuNeon}};
  for (const auto& level : levels) {
    if ((detected & level.flags) == level.flags) variants.push_back({level.name, tables_for(level.flags)});
  }
  return variants;
}

std::vector<Kernel> all_kernels() {
  std::vector<Kernel> kernels;
  for (auto family : {transform_kernels, intra_kernels, color_kernels, motion_kernels, flow_kernels, filter_kernels,
                      pad_kernels}) {
    for (const Kernel& kernel : family()) kernels.push_back(kernel);
  }
  return kernels;
}

struct Options {
  uint64_t seed = std::random_device{}();
  int iterations = 2000;
  std::string kernel;  // empty: all
  bool bench = false;
};

bool parse(int argc, char** argv, Options* options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--bench") {
      options->bench = true;
    } else if (arg == "--seed" && has_value) {
      options->seed = std::strtoull(argv[++i], nullptr, 0);
    } else if (arg == "--iterations" && has_value) {
      options->iterations = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--kernel" && has_value) {
      options->kernel = argv[++i];
    } else {
      std::fprintf(
          stderr,
          "unknown or incomplete option '%s'\nusage: %s [--seed N] [--iterations N] [--kernel NAME] [--bench]\n",
          arg.c_str(), argv[0]);
      return false;
    }
  }
  return true;
}

// Each kernel's distinct variants: (variant index, its table), skipping levels that only
// repeat the entry of the level below.
std::vector<size_t> distinct_variants(const Kernel& kernel, const std::vector<Variant>& variants) {
  std::vector<size_t> result;
  for (size_t v = 1; v < variants.size(); ++v) {
    if (kernel.entry(variants[v].tables) != kernel.entry(variants[v - 1].tables)) result.push_back(v);
  }
  return result;
}

int run_checks(const std::vector<Kernel>& kernels, const std::vector<Variant>& variants, const Options& options) {
  int failures = 0, checked = 0;
  for (const Kernel& kernel : kernels) {
    const std::vector<size_t> tested = distinct_variants(kernel, variants);
    if (tested.empty()) std::printf("  %-20s c only\n", kernel.name);
    for (size_t v : tested) {
      // Each kernel/variant pair draws its inputs from its own stream of the seed.
      Random random(options.seed ^ (std::hash<std::string>{}(std::string(kernel.name) + variants[v].name)));
      const std::string failure = kernel.check(variants[0].tables, variants[v].tables, random, options.iterations);
      ++checked;
      if (failure.empty()) {
        std::printf("  %-20s %-7s ok\n", kernel.name, variants[v].name);
      } else {
        ++failures;
        std::printf("  %-20s %-7s FAILED: %s\n", kernel.name, variants[v].name, failure.c_str());
      }
    }
  }
  std::printf("%d of %d kernel variants match their reference (seed %llu)\n", checked - failures, checked,
              static_cast<unsigned long long>(options.seed));
  return failures == 0 ? 0 : 1;
}

double seconds_for(const Kernel& kernel, const Tables& table, int iterations) {
  const auto start = std::chrono::steady_clock::now();
  kernel.bench(table, iterations);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Reference and variant alternate in rounds and the fastest round of each counts, so
// both see the same machine state.
void run_bench(const std::vector<Kernel>& kernels, const std::vector<Variant>& variants) {
  constexpr int kRounds = 7, kIterations = 200000;
  std::printf("%-20s %-7s %12s %8s\n", "kernel", "variant", "ns/call", "speed");
  for (const Kernel& kernel : kernels) {
    std::vector<size_t> measured = {0};
    for (size_t v : distinct_variants(kernel, variants)) measured.push_back(v);
    std::vector<double> best(measured.size(), 1e30);
    for (int round = 0; round < kRounds; ++round) {
      for (size_t m = 0; m < measured.size(); ++m) {
        best[m] = std::min(best[m], seconds_for(kernel, variants[measured[m]].tables, kIterations));
      }
    }
    for (size_t m = 0; m < measured.size(); ++m) {
      std::printf("%-20s %-7s %12.1f %7.2fx\n", kernel.name, variants[measured[m]].name,
                  best[m] / kIterations * 1e9, best[0] / best[m]);
    }
  }
}

}  // namespace
}  // namespace svc::checkkernels

int main(int argc, char** argv) {
  using namespace svc::checkkernels;
  Options options;
  if (!parse(argc, argv, &options)) return 2;
  std::vector<Kernel> kernels = all_kernels();
  if (!options.kernel.empty()) {
    std::erase_if(kernels, [&](const Kernel& k) { return options.kernel != k.name; });
    if (kernels.empty()) {
      std::fprintf(stderr, "no kernel named '%s'\n", options.kernel.c_str());
      return 2;
    }
  }
  const std::vector<Variant> variants = variants_of_this_machine();
  std::printf("variants on this machine:");
  for (const Variant& variant : variants) std::printf(" %s", variant.name);
  std::printf("\n");
  if (options.bench) {
    run_bench(kernels, variants);
    return 0;
  }
  return run_checks(kernels, variants, options);
}
