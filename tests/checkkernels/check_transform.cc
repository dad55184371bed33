// SPDX-License-Identifier: BSD-2-Clause
// DCT, transform type and quantization kernels against their references.
#include <cmath>
#include <string>

#include "checkkernels/harness.h"
#include "codec/common/dct.h"
#include "codec/common/quant.h"

namespace svc::checkkernels {
namespace {

constexpr int kIndex8x8 = codec::size_index(codec::TransformSize::k8x8);
constexpr int kIndex4x4 = codec::size_index(codec::TransformSize::k4x4);
constexpr int kIndex16x16 = codec::size_index(codec::TransformSize::k16x16);

// Samples as the codec feeds them: pixel - 128 (intra) or residuals in [-255, 255].
void random_samples(Random& random, float* samples) {
  const int range = random.uniform(0, 1) ? 128 : 255;
  const int pattern = random.uniform(0, 4);
  for (int i = 0; i < 64; ++i) {
    if (pattern == 0)
      samples[i] = static_cast<float>(range);
    else if (pattern == 1)
      samples[i] = static_cast<float>(((i + i / 8) & 1) ? range : -range);
    else
      samples[i] = static_cast<float>(random.uniform(-range, range));
  }
}

std::string check_forward_dct(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    float samples[64], expected[64], actual[64];
    random_samples(random, samples);
    reference.forward_dct_8x8(samples, expected);
    variant.forward_dct_8x8(samples, actual);
    if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) return diff;
  }
  return {};
}

// Coefficients in the inverse's domain: dense, sparse, DC only, one row, extremes.
void random_coefficients(Random& random, int16_t* coefficients) {
  const int pattern = random.uniform(0, 5);
  for (int i = 0; i < 64; ++i) coefficients[i] = 0;
  auto value = [&] { return static_cast<int16_t>(random.uniform(codec::kMinCoefficient, codec::kMaxCoefficient)); };
  switch (pattern) {
    case 0:
      for (int i = 0; i < 64; ++i) coefficients[i] = value();
      break;
    case 1:
      for (int k = random.uniform(1, 6); k > 0; --k) coefficients[random.uniform(0, 63)] = value();
      break;
    case 2: coefficients[0] = random.uniform(0, 1) ? value() : (random.uniform(0, 1) ? -2048 : 2047); break;
    case 3: {
      const int row = random.uniform(0, 7);
      for (int u = 0; u < 8; ++u) coefficients[8 * row + u] = value();
      break;
    }
    case 4:
      for (int i = 0; i < 64; ++i) coefficients[i] = ((i * 7 + i / 8) & 1) ? 2047 : -2048;
      break;
    default:
      for (int i = 0; i < 64; ++i) coefficients[i] = random.uniform(0, 1) ? 2047 : -2048;
  }
}

std::string check_inverse_dct(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    int16_t coefficients[64], expected[64], actual[64];
    random_coefficients(random, coefficients);
    reference.inverse_transform[kIndex8x8][0](coefficients, expected);
    variant.inverse_transform[kIndex8x8][0](coefficients, actual);
    if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) return diff;
  }
  return {};
}

// Flat or weighted steps, and the rounding offsets of plain rounding, the MPEG-style
// intra bias or the residuals' dead zone.
codec::Quantizer random_quantizer(Random& random) {
  const auto matrix = random.uniform(0, 1) ? codec::ResidualMatrix::kWeighted : codec::ResidualMatrix::kFlat;
  codec::Quantizer q =
      codec::make_residual_quantizer(codec::TransformSize::k8x8,
                                     random.uniform(0, 3) == 0
                                         ? (random.uniform(0, 1) ? codec::kMinQIndex : codec::kMaxQIndex)
                                         : random.uniform(codec::kMinQIndex, codec::kMaxQIndex),
                                     matrix);
  const float roundings[] = {0.5f, 0.34f, 0.2f};
  q.rounding_dc = roundings[random.uniform(0, 2)];
  q.rounding_ac = roundings[random.uniform(0, 2)];
  return q;
}

// Coefficients spread over the whole range, some exactly on a rounding boundary (where
// |c| * inverse_step + rounding is an integer) or beyond the largest level.
void random_dct_output(Random& random, const codec::Quantizer& q, float* coefficients) {
  for (int i = 0; i < 64; ++i) {
    const float rounding = i == 0 ? q.rounding_dc : q.rounding_ac;
    switch (random.uniform(0, 5)) {
      case 0: coefficients[i] = 0.0f; break;
      case 1: coefficients[i] = (static_cast<float>(random.uniform(0, 40)) - rounding) / q.inverse_step[i]; break;
      case 2: coefficients[i] = random.uniform_float(-1e6f, 1e6f); break;
      case 3: coefficients[i] = -0.0f; break;
      default: coefficients[i] = random.uniform_float(-2100.0f, 2100.0f);
    }
    if (random.uniform(0, 1)) coefficients[i] = -coefficients[i];
  }
}

std::string check_quantize(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const codec::Quantizer q = random_quantizer(random);
    float coefficients[64];
    random_dct_output(random, q, coefficients);
    int16_t expected[64], actual[64];
    const int expected_count =
        reference.quantize_8x8(coefficients, q.inverse_step.data(), q.rounding_dc, q.rounding_ac, expected);
    const int actual_count =
        variant.quantize_8x8(coefficients, q.inverse_step.data(), q.rounding_dc, q.rounding_ac, actual);
    const std::string input = " (qindex " + std::to_string(q.qindex) + ")";
    if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) return diff + input;
    if (expected_count != actual_count) {
      return "non-zero count: reference " + std::to_string(expected_count) + ", variant " +
             std::to_string(actual_count) + input;
    }
  }
  return {};
}

std::string check_dequantize(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const codec::Quantizer q = random_quantizer(random);
    int16_t levels[64], expected[64], actual[64];
    const int pattern = random.uniform(0, 3);
    for (int i = 0; i < 64; ++i) {
      if (pattern == 0)
        levels[i] = static_cast<int16_t>(random.uniform(-codec::kMaxLevel, codec::kMaxLevel));
      else if (pattern == 1)
        levels[i] = static_cast<int16_t>(random.uniform(0, 7) ? 0 : random.uniform(-40, 40));
      else if (pattern == 2)
        levels[i] = static_cast<int16_t>(random.uniform(0, 1) ? 32767 : -32768);
      else
        levels[i] = static_cast<int16_t>(random.uniform(0, 1) ? codec::kMaxLevel : -codec::kMaxLevel);
    }
    reference.dequantize_8x8(levels, q.scale.data(), expected);
    variant.dequantize_8x8(levels, q.scale.data(), actual);
    if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) {
      return diff + " (qindex " + std::to_string(q.qindex) + ")";
    }
  }
  return {};
}

void bench_forward_dct(const Tables& table, int iterations) {
  float samples[64], coefficients[64];
  for (int i = 0; i < 64; ++i) samples[i] = static_cast<float>((i * 37) % 255 - 128);
  for (int n = 0; n < iterations; ++n) {
    samples[n & 63] += 1.0f;
    table.forward_dct_8x8(samples, coefficients);
  }
  bench_sink = static_cast<int>(coefficients[0]);
}

void bench_inverse_dct(const Tables& table, int iterations) {
  int16_t coefficients[64], samples[64];
  for (int i = 0; i < 64; ++i) coefficients[i] = static_cast<int16_t>(i < 20 ? (i * 53) % 200 - 100 : 0);
  for (int n = 0; n < iterations; ++n) {
    coefficients[n & 15] ^= 1;
    table.inverse_transform[kIndex8x8][0](coefficients, samples);
  }
  bench_sink = samples[0];
}

void bench_quantize(const Tables& table, int iterations) {
  const codec::Quantizer q = codec::make_residual_quantizer(codec::TransformSize::k8x8, 8);
  float coefficients[64];
  int16_t levels[64];
  for (int i = 0; i < 64; ++i) coefficients[i] = static_cast<float>((i * 97) % 400 - 200);
  int sum = 0;
  for (int n = 0; n < iterations; ++n) {
    coefficients[n & 63] += 0.5f;
    sum += table.quantize_8x8(coefficients, q.inverse_step.data(), q.rounding_dc, q.rounding_ac, levels);
  }
  bench_sink = sum;
}

void bench_dequantize(const Tables& table, int iterations) {
  const codec::Quantizer q =
      codec::make_residual_quantizer(codec::TransformSize::k8x8, 8, codec::ResidualMatrix::kWeighted);
  int16_t levels[64], coefficients[64];
  for (int i = 0; i < 64; ++i) levels[i] = static_cast<int16_t>(i < 16 ? (i * 13) % 30 - 15 : 0);
  for (int n = 0; n < iterations; ++n) {
    levels[n & 15] ^= 1;
    table.dequantize_8x8(levels, q.scale.data(), coefficients);
  }
  bench_sink = coefficients[0];
}

// 4x4 and 16x16: the same input patterns over N x N blocks.
template <int N>
std::string check_forward_dct_n(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  auto forward = [](const Tables& t) { return N == 4 ? t.forward_dct_4x4 : t.forward_dct_16x16; };
  for (int n = 0; n < iterations; ++n) {
    float samples[N * N], expected[N * N], actual[N * N];
    const int range = random.uniform(0, 1) ? 128 : 255, pattern = random.uniform(0, 4);
    for (int i = 0; i < N * N; ++i) {
      samples[i] = pattern == 0   ? static_cast<float>(range)
                   : pattern == 1 ? static_cast<float>(((i + i / N) & 1) ? range : -range)
                                  : static_cast<float>(random.uniform(-range, range));
    }
    forward(reference)(samples, expected);
    forward(variant)(samples, actual);
    if (auto diff = first_difference(expected, actual, N * N, N); !diff.empty()) return diff;
  }
  return {};
}

template <int N>
std::string check_inverse_dct_n(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  auto inverse = [](const Tables& t) { return t.inverse_transform[N == 4 ? kIndex4x4 : kIndex16x16][0]; };
  for (int n = 0; n < iterations; ++n) {
    int16_t coefficients[N * N] = {}, expected[N * N], actual[N * N];
    const int pattern = random.uniform(0, 4);
    for (int i = 0; i < N * N; ++i) {
      const auto value = static_cast<int16_t>(random.uniform(codec::kMinCoefficient, codec::kMaxCoefficient));
      if (pattern == 0 || (pattern == 1 && random.uniform(0, 7) == 0)) coefficients[i] = value;
      if (pattern == 2) coefficients[i] = ((i * 7 + i / N) & 1) ? 2047 : -2048;  // saturates the output
      if (pattern == 3) coefficients[i] = random.uniform(0, 1) ? 2047 : -2048;
    }
    if (pattern == 4) coefficients[0] = static_cast<int16_t>(random.uniform(-2048, 2047));
    inverse(reference)(coefficients, expected);
    inverse(variant)(coefficients, actual);
    if (auto diff = first_difference(expected, actual, N * N, N); !diff.empty()) return diff;
  }
  return {};
}

template <int N>
void bench_forward_dct_n(const Tables& table, int iterations) {
  const auto forward = N == 4 ? table.forward_dct_4x4 : table.forward_dct_16x16;
  float samples[N * N], coefficients[N * N];
  for (int i = 0; i < N * N; ++i) samples[i] = static_cast<float>((i * 37) % 255 - 128);
  for (int n = 0; n < iterations; ++n) {
    samples[n % (N * N)] += 1.0f;
    forward(samples, coefficients);
  }
  bench_sink = static_cast<int>(coefficients[0]);
}

template <int N>
void bench_inverse_dct_n(const Tables& table, int iterations) {
  const auto inverse = table.inverse_transform[N == 4 ? kIndex4x4 : kIndex16x16][0];
  int16_t coefficients[N * N], samples[N * N];
  for (int i = 0; i < N * N; ++i) coefficients[i] = static_cast<int16_t>(i < 20 ? (i * 53) % 200 - 100 : 0);
  for (int n = 0; n < iterations; ++n) {
    coefficients[n & 15] ^= 1;
    inverse(coefficients, samples);
  }
  bench_sink = samples[0];
}

// The intra transform types, over the same input patterns as the DCTs of their size, each
// type in turn: 1..3 (DST-VII in one or both directions) for squares, 0..3 for the
// rectangular blocks (W x H), whose DCT_DCT is a typed kernel too.
template <int W, int H>
auto forward_typed_of(const Tables& t) {
  if constexpr (W == 16 && H == 4) return t.forward_typed_16x4;
  if constexpr (W == 4 && H == 16) return t.forward_typed_4x16;
  if constexpr (W == 8 && H == 4) return t.forward_typed_8x4;
  if constexpr (W == 4 && H == 8) return t.forward_typed_4x8;
  if constexpr (W != H && W != 4 && H != 4) return W == 16 ? t.forward_typed_16x8 : t.forward_typed_8x16;
  return W == 4 ? t.forward_typed_4x4 : W == 8 ? t.forward_typed_8x8 : t.forward_typed_16x16;
}
// The inverses of the W x H size, indexed by type.
template <int W, int H>
const auto& inverse_typed_of(const Tables& t) {
  return t.inverse_transform[codec::size_index(codec::transform_size_of(W, H))];
}
template <int W, int H>
int type_of_iteration(int n) {
  return W == H ? 1 + n % 3 : n % 4;
}

template <int W, int H>
std::string check_forward_typed(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    float samples[W * H], expected[W * H], actual[W * H];
    const int range = random.uniform(0, 1) ? 128 : 255, pattern = random.uniform(0, 4);
    for (int i = 0; i < W * H; ++i) {
      samples[i] = pattern == 0   ? static_cast<float>(range)
                   : pattern == 1 ? static_cast<float>(((i + i / W) & 1) ? range : -range)
                                  : static_cast<float>(random.uniform(-range, range));
    }
    const int type = type_of_iteration<W, H>(n);
    forward_typed_of<W, H>(reference)(type, samples, expected);
    forward_typed_of<W, H>(variant)(type, samples, actual);
    if (auto diff = first_difference(expected, actual, W * H, W); !diff.empty()) {
      return "type " + std::to_string(type) + ": " + diff;
    }
  }
  return {};
}

template <int W, int H>
std::string check_inverse_typed(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    int16_t coefficients[W * H] = {}, expected[W * H], actual[W * H];
    const int pattern = random.uniform(0, 4);
    for (int i = 0; i < W * H; ++i) {
      const auto value = static_cast<int16_t>(random.uniform(codec::kMinCoefficient, codec::kMaxCoefficient));
      if (pattern == 0 || (pattern == 1 && random.uniform(0, 7) == 0)) coefficients[i] = value;
      if (pattern == 2) coefficients[i] = ((i * 7 + i / W) & 1) ? 2047 : -2048;  // saturates the output
      if (pattern == 3) coefficients[i] = random.uniform(0, 1) ? 2047 : -2048;
    }
    if (pattern == 4) coefficients[0] = static_cast<int16_t>(random.uniform(-2048, 2047));
    const int type = type_of_iteration<W, H>(n);
    inverse_typed_of<W, H>(reference)[type](coefficients, expected);
    inverse_typed_of<W, H>(variant)[type](coefficients, actual);
    if (auto diff = first_difference(expected, actual, W * H, W); !diff.empty()) {
      return "type " + std::to_string(type) + ": " + diff;
    }
  }
  return {};
}

template <int W, int H>
void bench_forward_typed(const Tables& table, int iterations) {
  float samples[W * H], coefficients[W * H];
  for (int i = 0; i < W * H; ++i) samples[i] = static_cast<float>((i * 37) % 255 - 128);
  for (int n = 0; n < iterations; ++n) {
    samples[n % (W * H)] += 1.0f;
    forward_typed_of<W, H>(table)(type_of_iteration<W, H>(n), samples, coefficients);
  }
  bench_sink = static_cast<int>(coefficients[0]);
}

template <int W, int H>
void bench_inverse_typed(const Tables& table, int iterations) {
  int16_t coefficients[W * H], samples[W * H];
  for (int i = 0; i < W * H; ++i) coefficients[i] = static_cast<int16_t>(i < 20 ? (i * 53) % 200 - 100 : 0);
  for (int n = 0; n < iterations; ++n) {
    coefficients[n & 15] ^= 1;
    inverse_typed_of<W, H>(table)[type_of_iteration<W, H>(n)](coefficients, samples);
  }
  bench_sink = samples[0];
}

// The inverse_transform_add kernel of W x H and `Type`: the inverses' coefficient
// patterns, predictions with extremes, strides from the block width to 40, destinations
// apart from the prediction or the prediction itself; the whole destination buffer is
// compared, so that a write outside the block shows.
template <int W, int H>
constexpr int add_index = codec::size_index(codec::transform_size_of(W, H));

template <int W, int H, int Type>
std::string check_inverse_add(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  constexpr int kMaxStride = 40;
  const auto add_of = [](const Tables& t) { return t.inverse_transform_add[add_index<W, H>][Type]; };
  Buffer prediction(H * kMaxStride), expected(H * kMaxStride), actual(H * kMaxStride);
  for (int n = 0; n < iterations; ++n) {
    int16_t coefficients[W * H] = {};
    const int pattern = random.uniform(0, 4);
    for (int i = 0; i < W * H; ++i) {
      const auto value = static_cast<int16_t>(random.uniform(codec::kMinCoefficient, codec::kMaxCoefficient));
      if (pattern == 0 || (pattern == 1 && random.uniform(0, 7) == 0)) coefficients[i] = value;
      if (pattern == 2) coefficients[i] = ((i * 7 + i / W) & 1) ? 2047 : -2048;
      if (pattern == 3) coefficients[i] = random.uniform(0, 1) ? 2047 : -2048;
    }
    if (pattern == 4) coefficients[0] = static_cast<int16_t>(random.uniform(-2048, 2047));
    const int prediction_stride = random.uniform(W, kMaxStride), dst_stride = random.uniform(W, kMaxStride);
    const bool in_place = random.uniform(0, 3) == 0;
    const size_t bytes = static_cast<size_t>(H) * kMaxStride;
    random.fill_with_extremes(prediction.at(0), bytes);
    std::memcpy(expected.at(0), prediction.at(0), bytes);
    std::memcpy(actual.at(0), prediction.at(0), bytes);
    if (in_place) {
      add_of(reference)(coefficients, expected.at(0), prediction_stride, expected.at(0), prediction_stride);
      add_of(variant)(coefficients, actual.at(0), prediction_stride, actual.at(0), prediction_stride);
    } else {
      add_of(reference)(coefficients, prediction.at(0), prediction_stride, expected.at(0), dst_stride);
      add_of(variant)(coefficients, prediction.at(0), prediction_stride, actual.at(0), dst_stride);
    }
    if (auto diff = first_difference(expected.at(0), actual.at(0), bytes, kMaxStride); !diff.empty()) {
      return std::string(in_place ? "in place, " : "") + "pattern " + std::to_string(pattern) + ": " + diff;
    }
  }
  return {};
}

template <int W, int H, int Type>
void bench_inverse_add(const Tables& table, int iterations) {
  const auto add = table.inverse_transform_add[add_index<W, H>][Type];
  int16_t coefficients[W * H];
  uint8_t block[W * H];
  for (int i = 0; i < W * H; ++i) {
    coefficients[i] = static_cast<int16_t>(i < 20 ? (i * 53) % 200 - 100 : 0);
    block[i] = static_cast<uint8_t>(i * 7);
  }
  for (int n = 0; n < iterations; ++n) {
    coefficients[n & 15] ^= 1;
    add(coefficients, block, W, block, W);
  }
  bench_sink = block[0];
}

template <int W, int H, int Type>
Kernel inverse_add_kernel() {
  static const std::string name =
      "inverse_transform_add_" + std::to_string(W) + "x" + std::to_string(H) + "_type" + std::to_string(Type);
  return {name.c_str(), [](const Tables& t) { return entry_of(t.inverse_transform_add[add_index<W, H>][Type]); },
          check_inverse_add<W, H, Type>, bench_inverse_add<W, H, Type>};
}

template <int W, int H>
void add_inverse_add_kernels(std::vector<Kernel>* kernels) {
  kernels->push_back(inverse_add_kernel<W, H, 0>());
  kernels->push_back(inverse_add_kernel<W, H, 1>());
  kernels->push_back(inverse_add_kernel<W, H, 2>());
  kernels->push_back(inverse_add_kernel<W, H, 3>());
}

}  // namespace

std::vector<Kernel> transform_kernels() {
  std::vector<Kernel> kernels = {
      {"forward_dct_8x8", [](const Tables& t) { return entry_of(t.forward_dct_8x8); }, check_forward_dct,
       bench_forward_dct},
      {"inverse_dct_8x8", [](const Tables& t) { return entry_of(t.inverse_transform[kIndex8x8][0]); },
       check_inverse_dct, bench_inverse_dct},
      {"quantize_8x8", [](const Tables& t) { return entry_of(t.quantize_8x8); }, check_quantize, bench_quantize},
      {"dequantize_8x8", [](const Tables& t) { return entry_of(t.dequantize_8x8); }, check_dequantize,
       bench_dequantize},
      {"forward_dct_4x4", [](const Tables& t) { return entry_of(t.forward_dct_4x4); }, check_forward_dct_n<4>,
       bench_forward_dct_n<4>},
      {"forward_dct_16x16", [](const Tables& t) { return entry_of(t.forward_dct_16x16); }, check_forward_dct_n<16>,
       bench_forward_dct_n<16>},
      {"inverse_dct_4x4", [](const Tables& t) { return entry_of(t.inverse_transform[kIndex4x4][0]); },
       check_inverse_dct_n<4>, bench_inverse_dct_n<4>},
      {"inverse_dct_16x16", [](const Tables& t) { return entry_of(t.inverse_transform[kIndex16x16][0]); },
       check_inverse_dct_n<16>, bench_inverse_dct_n<16>},
      {"forward_typed_4x4", [](const Tables& t) { return entry_of(t.forward_typed_4x4); },
       check_forward_typed<4, 4>, bench_forward_typed<4, 4>},
      {"inverse_typed_4x4", [](const Tables& t) { return entry_of(inverse_typed_of<4, 4>(t)[1]); },
       check_inverse_typed<4, 4>, bench_inverse_typed<4, 4>},
      {"forward_typed_8x8", [](const Tables& t) { return entry_of(t.forward_typed_8x8); },
       check_forward_typed<8, 8>, bench_forward_typed<8, 8>},
      {"inverse_typed_8x8", [](const Tables& t) { return entry_of(inverse_typed_of<8, 8>(t)[1]); },
       check_inverse_typed<8, 8>, bench_inverse_typed<8, 8>},
      {"forward_typed_16x16", [](const Tables& t) { return entry_of(t.forward_typed_16x16); },
       check_forward_typed<16, 16>, bench_forward_typed<16, 16>},
      {"inverse_typed_16x16", [](const Tables& t) { return entry_of(inverse_typed_of<16, 16>(t)[1]); },
       check_inverse_typed<16, 16>, bench_inverse_typed<16, 16>},
      {"forward_typed_16x8", [](const Tables& t) { return entry_of(t.forward_typed_16x8); },
       check_forward_typed<16, 8>, bench_forward_typed<16, 8>},
      {"inverse_typed_16x8", [](const Tables& t) { return entry_of(inverse_typed_of<16, 8>(t)[1]); },
       check_inverse_typed<16, 8>, bench_inverse_typed<16, 8>},
      {"forward_typed_8x16", [](const Tables& t) { return entry_of(t.forward_typed_8x16); },
       check_forward_typed<8, 16>, bench_forward_typed<8, 16>},
      {"inverse_typed_8x16", [](const Tables& t) { return entry_of(inverse_typed_of<8, 16>(t)[1]); },
       check_inverse_typed<8, 16>, bench_inverse_typed<8, 16>},
      {"forward_typed_16x4", [](const Tables& t) { return entry_of(t.forward_typed_16x4); },
       check_forward_typed<16, 4>, bench_forward_typed<16, 4>},
      {"inverse_typed_16x4", [](const Tables& t) { return entry_of(inverse_typed_of<16, 4>(t)[1]); },
       check_inverse_typed<16, 4>, bench_inverse_typed<16, 4>},
      {"forward_typed_4x16", [](const Tables& t) { return entry_of(t.forward_typed_4x16); },
       check_forward_typed<4, 16>, bench_forward_typed<4, 16>},
      {"inverse_typed_4x16", [](const Tables& t) { return entry_of(inverse_typed_of<4, 16>(t)[1]); },
       check_inverse_typed<4, 16>, bench_inverse_typed<4, 16>},
      {"forward_typed_8x4", [](const Tables& t) { return entry_of(t.forward_typed_8x4); },
       check_forward_typed<8, 4>, bench_forward_typed<8, 4>},
      {"inverse_typed_8x4", [](const Tables& t) { return entry_of(inverse_typed_of<8, 4>(t)[1]); },
       check_inverse_typed<8, 4>, bench_inverse_typed<8, 4>},
      {"forward_typed_4x8", [](const Tables& t) { return entry_of(t.forward_typed_4x8); },
       check_forward_typed<4, 8>, bench_forward_typed<4, 8>},
      {"inverse_typed_4x8", [](const Tables& t) { return entry_of(inverse_typed_of<4, 8>(t)[1]); },
       check_inverse_typed<4, 8>, bench_inverse_typed<4, 8>},
  };
  add_inverse_add_kernels<8, 8>(&kernels);
  add_inverse_add_kernels<4, 4>(&kernels);
  add_inverse_add_kernels<16, 16>(&kernels);
  add_inverse_add_kernels<16, 8>(&kernels);
  add_inverse_add_kernels<8, 16>(&kernels);
  add_inverse_add_kernels<16, 4>(&kernels);
  add_inverse_add_kernels<4, 16>(&kernels);
  add_inverse_add_kernels<8, 4>(&kernels);
  add_inverse_add_kernels<4, 8>(&kernels);
  return kernels;
}

}  // namespace svc::checkkernels
