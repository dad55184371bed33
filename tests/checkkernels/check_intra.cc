// SPDX-License-Identifier: BSD-2-Clause
// Intra prediction, chroma-from-luma and SATD kernels against their references.
#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

constexpr int k8x8 = codec::size_index(codec::TransformSize::k8x8);

// Edges as the codec builds them: random, flat, a step between left and above,
// alternating extremes.
void random_edge(Random& random, uint8_t* edge) {
  const int pattern = random.uniform(0, 3);
  if (pattern == 0) {
    random.fill_with_extremes(edge, codec::dsp::kIntraEdgeSamples);
  } else if (pattern == 1) {
    const uint8_t left = random.byte(), above = random.byte();
    for (int i = 0; i < codec::dsp::kIntraEdgeSamples; ++i) edge[i] = i < 16 ? left : above;
  } else {
    random.fill(edge, codec::dsp::kIntraEdgeSamples);
  }
}

std::string check_intra_predict(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    uint8_t edge[codec::dsp::kIntraEdgeSamples], expected[64], actual[64];
    random_edge(random, edge);
    for (int mode = 0; mode < 35; ++mode) {
      reference.intra_predict[k8x8](edge, mode, expected);
      variant.intra_predict[k8x8](edge, mode, actual);
      if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) {
        return "mode " + std::to_string(mode) + ": " + diff;
      }
    }
  }
  return {};
}

// The N x N SATD of a table.
template <int N>
auto satd_of(const Tables& t) {
  if constexpr (N == 4)
    return t.satd_4x4;
  else if constexpr (N == 8)
    return t.satd_8x8;
  else
    return t.satd_16x16;
}

// Any source stride and alignment, random or extreme samples.
template <int N>
std::string check_satd(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  Buffer source(N * (N + 32) + 16), prediction(N * N);
  for (int n = 0; n < iterations; ++n) {
    const int stride = random.uniform(N, N + 32), offset = random.uniform(0, 15);
    uint8_t* s = source.at(offset);
    random.fill_with_extremes(s, static_cast<size_t>((N - 1) * stride + N));
    random.fill_with_extremes(prediction.at(0), N * N);
    const int expected = satd_of<N>(reference)(s, stride, prediction.at(0));
    const int actual = satd_of<N>(variant)(s, stride, prediction.at(0));
    if (expected != actual) {
      return "stride " + std::to_string(stride) + ": reference " + std::to_string(expected) + ", variant " +
             std::to_string(actual);
    }
  }
  return {};
}

// The W x H predictor of a table.
template <int W, int H>
auto predictor_of(const Tables& t) {
  return t.intra_predict[codec::size_index(codec::transform_size_of(W, H))];
}
// 4x4, 16x16 and the rectangular blocks from edges of 2 (W + H) + 1 samples built the same ways.
template <int N, int H = N>
std::string check_intra_predict_n(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  constexpr int W = N, kSamples = 2 * (W + H) + 1;
  for (int n = 0; n < iterations; ++n) {
    uint8_t edge[kSamples], expected[W * H], actual[W * H];
    const int pattern = random.uniform(0, 2);
    if (pattern == 0) {
      random.fill_with_extremes(edge, kSamples);
    } else if (pattern == 1) {
      const uint8_t left = random.byte(), above = random.byte();
      for (int i = 0; i < kSamples; ++i) edge[i] = i < W + H ? left : above;
    } else {
      random.fill(edge, kSamples);
    }
    for (int mode = 0; mode < 35; ++mode) {
      predictor_of<W, H>(reference)(edge, mode, expected);
      predictor_of<W, H>(variant)(edge, mode, actual);
      if (auto diff = first_difference(expected, actual, W * H, W); !diff.empty()) {
        return "mode " + std::to_string(mode) + ": " + diff;
      }
    }
  }
  return {};
}

template <int N, int H = N>
void bench_intra_predict_n(const Tables& table, int iterations) {
  const auto predict = predictor_of<N, H>(table);
  uint8_t edge[2 * (N + H) + 1], out[N * H];
  for (int i = 0; i < 2 * (N + H) + 1; ++i) edge[i] = static_cast<uint8_t>(i * 7);
  for (int n = 0; n < iterations; ++n) predict(edge, n % 35, out);
  bench_sink = out[0];
}

void bench_intra_predict(const Tables& table, int iterations) {
  uint8_t edge[codec::dsp::kIntraEdgeSamples], out[64];
  for (int i = 0; i < codec::dsp::kIntraEdgeSamples; ++i) edge[i] = static_cast<uint8_t>(i * 7);
  for (int n = 0; n < iterations; ++n) table.intra_predict[k8x8](edge, n % 35, out);
  bench_sink = out[0];
}

template <int N>
void bench_satd(const Tables& table, int iterations) {
  uint8_t source[N * N], prediction[N * N];
  for (int i = 0; i < N * N; ++i) {
    source[i] = static_cast<uint8_t>(i * 37);
    prediction[i] = static_cast<uint8_t>(i * 11);
  }
  int sum = 0;
  for (int n = 0; n < iterations; ++n) {
    source[n % (N * N)] ^= 1;
    sum += satd_of<N>(table)(source, N, prediction);
  }
  bench_sink = sum;
}

// Luma as the codec holds it: any stride from 16, random or extreme samples, sometimes
// flat (every AC value 0).
std::string check_cfl_luma_ac(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  Buffer luma(16 * 48);
  for (int n = 0; n < iterations; ++n) {
    const int stride = random.uniform(16, 48), offset = random.uniform(0, 15);
    uint8_t* l = luma.at(offset);
    if (random.uniform(0, 7) == 0) {
      std::memset(l, random.byte(), static_cast<size_t>(15 * stride + 16));
    } else {
      random.fill_with_extremes(l, static_cast<size_t>(15 * stride + 16));
    }
    int16_t expected[64], actual[64];
    reference.cfl_luma_ac_8x8(l, stride, expected);
    variant.cfl_luma_ac_8x8(l, stride, actual);
    if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) {
      return "stride " + std::to_string(stride) + ": " + diff;
    }
  }
  return {};
}

// AC from the reference kernel on random or extreme luma, or at the contract's limits;
// every alpha and DC values including 0 and 255 (saturation).
std::string check_cfl_predict(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    int16_t ac[64];
    if (random.uniform(0, 3) == 0) {
      for (int16_t& v : ac) v = static_cast<int16_t>(random.uniform(0, 1) ? random.uniform(-1020, 1020) : 1020);
    } else {
      uint8_t luma[256];
      random.fill_with_extremes(luma, sizeof luma);
      reference.cfl_luma_ac_8x8(luma, 16, ac);
    }
    const int dc = random.uniform(0, 3) == 0 ? 255 * random.uniform(0, 1) : random.byte();
    for (int alpha = -16; alpha <= 16; ++alpha) {
      uint8_t expected[64], actual[64];
      reference.cfl_predict_8x8(ac, dc, alpha, expected);
      variant.cfl_predict_8x8(ac, dc, alpha, actual);
      if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) {
        return "dc " + std::to_string(dc) + ", alpha " + std::to_string(alpha) + ": " + diff;
      }
    }
  }
  return {};
}

void bench_cfl_luma_ac(const Tables& table, int iterations) {
  uint8_t luma[256];
  for (int i = 0; i < 256; ++i) luma[i] = static_cast<uint8_t>(i * 37);
  int16_t ac[64];
  for (int n = 0; n < iterations; ++n) {
    luma[n & 255] ^= 1;
    table.cfl_luma_ac_8x8(luma, 16, ac);
  }
  bench_sink = ac[0];
}

void bench_cfl_predict(const Tables& table, int iterations) {
  int16_t ac[64];
  for (int i = 0; i < 64; ++i) ac[i] = static_cast<int16_t>(i * 29 - 900);
  uint8_t out[64];
  for (int n = 0; n < iterations; ++n) table.cfl_predict_8x8(ac, n & 255, n % 33 - 16, out);
  bench_sink = out[0];
}

}  // namespace

std::vector<Kernel> intra_kernels() {
  return {
      {"intra_predict_8x8", [](const Tables& t) { return entry_of(t.intra_predict[k8x8]); }, check_intra_predict,
       bench_intra_predict},
      {"satd_8x8", [](const Tables& t) { return entry_of(satd_of<8>(t)); }, check_satd<8>, bench_satd<8>},
      {"satd_16x16", [](const Tables& t) { return entry_of(satd_of<16>(t)); }, check_satd<16>, bench_satd<16>},
      {"intra_predict_4x4", [](const Tables& t) { return entry_of(predictor_of<4, 4>(t)); },
       check_intra_predict_n<4>, bench_intra_predict_n<4>},
      {"intra_predict_16x16", [](const Tables& t) { return entry_of(predictor_of<16, 16>(t)); },
       check_intra_predict_n<16>, bench_intra_predict_n<16>},
      {"intra_predict_16x8", [](const Tables& t) { return entry_of(predictor_of<16, 8>(t)); },
       check_intra_predict_n<16, 8>, bench_intra_predict_n<16, 8>},
      {"intra_predict_8x16", [](const Tables& t) { return entry_of(predictor_of<8, 16>(t)); },
       check_intra_predict_n<8, 16>, bench_intra_predict_n<8, 16>},
      {"intra_predict_16x4", [](const Tables& t) { return entry_of(predictor_of<16, 4>(t)); },
       check_intra_predict_n<16, 4>, bench_intra_predict_n<16, 4>},
      {"intra_predict_4x16", [](const Tables& t) { return entry_of(predictor_of<4, 16>(t)); },
       check_intra_predict_n<4, 16>, bench_intra_predict_n<4, 16>},
      {"intra_predict_8x4", [](const Tables& t) { return entry_of(predictor_of<8, 4>(t)); },
       check_intra_predict_n<8, 4>, bench_intra_predict_n<8, 4>},
      {"intra_predict_4x8", [](const Tables& t) { return entry_of(predictor_of<4, 8>(t)); },
       check_intra_predict_n<4, 8>, bench_intra_predict_n<4, 8>},
      {"satd_4x4", [](const Tables& t) { return entry_of(satd_of<4>(t)); }, check_satd<4>, bench_satd<4>},
      {"cfl_luma_ac_8x8", [](const Tables& t) { return entry_of(t.cfl_luma_ac_8x8); }, check_cfl_luma_ac,
       bench_cfl_luma_ac},
      {"cfl_predict_8x8", [](const Tables& t) { return entry_of(t.cfl_predict_8x8); }, check_cfl_predict,
       bench_cfl_predict},
  };
}

}  // namespace svc::checkkernels
