// SPDX-License-Identifier: BSD-2-Clause
// The range decoder's symbol search: distributions of every count 2..16 with random,
// repeated and extreme (0, 32767) cumulative entries and garbage in the unused ones,
// scales from 512 to 2^17 - 1, and codes on every bound, one either side of it and
// beyond 2^31, so that a variant must mask the unused entries and compare unsigned.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

constexpr int kEntries = 16;
constexpr uint32_t kMinScale = 512, kMaxScale = (1u << 17) - 1;

struct alignas(32) Distribution {
  uint16_t cumulative[kEntries];
  int count;
};

uint16_t random_entry(Random& random) {
  switch (random.uniform(0, 5)) {
    case 0: return 0;
    case 1: return 32767;
    default: return static_cast<uint16_t>(random.uniform(0, 32767));
  }
}

// count - 1 non-decreasing entries: random, drawn from a few values (runs of equal
// entries), all one value or a ramp ending at the extremes; then the unused entries
// all 0xFFFF, all 0, random 16-bit values or the last entry repeated.
Distribution random_distribution(Random& random) {
  Distribution d{};
  d.count = random.uniform(0, 3) == 0 ? random.uniform(3, 4) : random.uniform(2, kEntries);
  const int used = d.count - 1;
  std::vector<uint16_t> values(static_cast<size_t>(used));
  switch (random.uniform(0, 4)) {
    case 0: {  // runs: a few distinct values
      const uint16_t choices[3] = {random_entry(random), random_entry(random), random_entry(random)};
      for (auto& v : values) v = choices[random.uniform(0, 2)];
      break;
    }
    case 1: {  // all equal
      const uint16_t v = random_entry(random);
      for (auto& e : values) e = v;
      break;
    }
    case 2:  // from 0 to 32767
      for (int k = 0; k < used; ++k)
        values[static_cast<size_t>(k)] = static_cast<uint16_t>(32767 * k / std::max(1, used - 1));
      break;
    default:
      for (auto& v : values) v = random_entry(random);
  }
  std::sort(values.begin(), values.end());
  for (int k = 0; k < used; ++k) d.cumulative[k] = values[static_cast<size_t>(k)];
  const int garbage = random.uniform(0, 3);
  for (int k = used; k < kEntries; ++k) {
    d.cumulative[k] = garbage == 0   ? 0xFFFF
                      : garbage == 1 ? 0
                      : garbage == 2 ? static_cast<uint16_t>(random.uniform(0, 0xFFFF))
                                     : (used > 0 ? d.cumulative[used - 1] : 0);
  }
  return d;
}

uint32_t random_scale(Random& random) {
  switch (random.uniform(0, 7)) {
    case 0: return kMinScale;
    case 1: return kMaxScale;
    case 2: return 1u << random.uniform(9, 16);         // powers of two, 65536 among them
    case 3: return (1u << random.uniform(10, 17)) - 1;  // one below, 65535 among them
    case 4: return static_cast<uint32_t>(random.uniform(65537, static_cast<int>(kMaxScale)));  // codes past 2^31
    default: return static_cast<uint32_t>(random.uniform(static_cast<int>(kMinScale), static_cast<int>(kMaxScale)));
  }
}

// The codes to try for one distribution and scale: 0, the top of the range and one past
// it, 2^31 and its neighbours, every bound and one either side, and random codes.
std::vector<uint32_t> codes_for(Random& random, const Distribution& d, uint32_t scale) {
  const uint64_t range = uint64_t{scale} * 32768;  // codes lie in [0, range)
  std::vector<uint32_t> codes = {0,
                                 1,
                                 static_cast<uint32_t>(range - 1),
                                 static_cast<uint32_t>(range),
                                 0x7FFFFFFFu,
                                 0x80000000u,
                                 0x80000001u,
                                 0xFFFFFFFFu};
  for (int k = 1; k < d.count; ++k) {
    const uint32_t bound = scale * d.cumulative[k - 1] + static_cast<uint32_t>(k);
    codes.insert(codes.end(), {bound - 1, bound, bound + 1});
  }
  for (int i = 0; i < 16; ++i) {
    const uint64_t code = (uint64_t{static_cast<uint32_t>(random.uniform(0, 0x7FFFFFFF))} << 17 ^
                           static_cast<uint32_t>(random.uniform(0, 0x1FFFF))) %
                          range;
    codes.push_back(static_cast<uint32_t>(code));
  }
  return codes;
}

std::string describe(const Distribution& d, uint32_t scale, uint32_t code) {
  std::string text = "count " + std::to_string(d.count) + ", scale " + std::to_string(scale) + ", code " +
                     std::to_string(code) + ", cumulative";
  for (int k = 0; k < kEntries; ++k)
    text.append(k == d.count - 1 ? " |" : " ").append(std::to_string(d.cumulative[k]));
  return text;
}

std::string check_find_symbol(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    const Distribution d = random_distribution(random);
    const uint32_t scale = random_scale(random);
    for (uint32_t code : codes_for(random, d, scale)) {
      const int expected = reference.find_symbol(d.cumulative, d.count, scale, code);
      const int got = variant.find_symbol(d.cumulative, d.count, scale, code);
      if (expected != got) {
        return "reference " + std::to_string(expected) + ", variant " + std::to_string(got) + " (" +
               describe(d, scale, code) + ")";
      }
    }
  }
  return {};
}

// 64 distributions of a decoder's mix (mostly 3 and 4 symbols, some 2 and 5 to 16),
// garbage in the unused entries, each with a code in its range, in turn.
void bench_find_symbol(const Tables& table, int iterations) {
  struct Case {
    Distribution d;
    uint32_t scale, code;
  };
  static const std::vector<Case> cases = [] {
    Random random(7);
    std::vector<Case> result;
    for (int i = 0; i < 64; ++i) {
      Case c;
      const int pick = random.uniform(0, 9);
      const int count = pick < 4 ? 3 : pick < 7 ? 4 : pick == 7 ? 2 : random.uniform(5, kEntries);
      for (int k = 0; k < kEntries; ++k) c.d.cumulative[k] = 0xFFFF;
      for (int k = 1; k < count; ++k) c.d.cumulative[k - 1] = static_cast<uint16_t>(32768 * k / count);
      c.d.count = count;
      c.scale = static_cast<uint32_t>(random.uniform(1 << 16, (1 << 17) - 1));
      c.code = static_cast<uint32_t>((uint64_t{c.scale} * 32768 * random.uniform(0, 1023)) >> 10);
      result.push_back(c);
    }
    return result;
  }();
  int sum = 0;
  for (int n = 0; n < iterations; ++n) {
    const Case& c = cases[static_cast<size_t>(n) & 63];
    sum += table.find_symbol(c.d.cumulative, c.d.count, c.scale, c.code);
  }
  bench_sink = sum;
}

}  // namespace

std::vector<Kernel> entropy_kernels() {
  return {
      {"find_symbol", [](const Tables& t) { return entry_of(t.find_symbol); }, check_find_symbol,
       bench_find_symbol},
  };
}

}  // namespace svc::checkkernels
