// SPDX-License-Identifier: BSD-2-Clause
// The kernel checker's shared parts: seeded random inputs, the comparison that names the
// first differing position, and the registry entry each kernel family provides.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "codec/common/dsp/dsp.h"
#include "codec/encoder/dsp/encoder_dsp.h"
#include "spatial/flow_kernels.h"

namespace svc::checkkernels {

// The shared kernels, the encoder's codec kernels and its flow kernels, built for one
// feature set. The two codec tables name no entry alike, so a check reads either's
// entries as members of Tables.
struct Tables : codec::dsp::DspTable, codec::dsp::EncoderDspTable {
  FlowKernels flow;
};

class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine_); }
  float uniform_float(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(engine_); }
  uint8_t byte() { return static_cast<uint8_t>(uniform(0, 255)); }
  void fill(uint8_t* data, size_t count) {
    for (size_t i = 0; i < count; ++i) data[i] = byte();
  }
  // Mostly random, sometimes all one extreme or alternating extremes (saturation).
  void fill_with_extremes(uint8_t* data, size_t count) {
    switch (uniform(0, 5)) {
      case 0: std::memset(data, 0, count); break;
      case 1: std::memset(data, 255, count); break;
      case 2:
        for (size_t i = 0; i < count; ++i) data[i] = (i & 1) ? 255 : 0;
        break;
      default: fill(data, count);
    }
  }

 private:
  std::mt19937_64 engine_;
};

// A value as text; floats with enough digits to tell neighbours apart.
template <typename T>
std::string to_text(T value) {
  if constexpr (std::is_floating_point_v<T>) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
    return text;
  } else {
    return std::to_string(+value);
  }
}

// "" when equal; otherwise where the first difference lies (x, y for width > 0).
template <typename T>
std::string first_difference(const T* reference, const T* variant, size_t count, size_t width = 0) {
  for (size_t i = 0; i < count; ++i) {
    if (std::memcmp(&reference[i], &variant[i], sizeof(T)) == 0) continue;
    std::string where = width > 0 ? "(x " + std::to_string(i % width) + ", y " + std::to_string(i / width) + ")"
                                  : "index " + std::to_string(i);
    return "first difference at " + where + ": reference " + to_text(reference[i]) + ", variant " +
           to_text(variant[i]);
  }
  return {};
}

// Buffers aligned to 64 bytes from which tests take deliberately unaligned pointers.
class Buffer {
 public:
  explicit Buffer(size_t size, uint8_t fill = 0xA5) : bytes_(size + 128, fill) {}
  uint8_t* at(size_t offset) {
    const auto base = reinterpret_cast<uintptr_t>(bytes_.data());
    return reinterpret_cast<uint8_t*>((base + 63) & ~uintptr_t{63}) + offset;
  }

 private:
  std::vector<uint8_t> bytes_;
};

template <typename Fn>
const void* entry_of(Fn fn) {
  return reinterpret_cast<const void*>(fn);
}

struct Kernel {
  const char* name;
  // The table entry, to tell whether a table holds a variant other than the reference.
  const void* (*entry)(const Tables& table);
  // Compares `variant` with `reference` on random inputs and edge cases: "" when they
  // agree, else a description of the first mismatch and its input.
  std::string (*check)(const Tables& reference, const Tables& variant, Random& random, int iterations);
  // Runs the kernel `iterations` times on fixed inputs (for --bench).
  void (*bench)(const Tables& table, int iterations);
};

std::vector<Kernel> transform_kernels();
std::vector<Kernel> color_kernels();
std::vector<Kernel> motion_kernels();
std::vector<Kernel> flow_kernels();
std::vector<Kernel> intra_kernels();
std::vector<Kernel> filter_kernels();
std::vector<Kernel> pad_kernels();

// Keeps benchmark results alive without I/O.
inline volatile int bench_sink = 0;

}  // namespace svc::checkkernels
