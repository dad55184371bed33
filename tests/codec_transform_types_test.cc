// SPDX-License-Identifier: BSD-2-Clause
// Intra transform types (DCT or DST-VII per direction): the integer matrices against
// the DST-VII formula, the integer inverses against their matrix products, forward then
// inverse near identity, the type's coding, and intra frames that choose every type.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "codec/common/dct.h"
#include "codec/common/dsp/transform_type_basis.h"
#include "codec/common/intra_frame.h"
#include "codec/common/intra_macroblock.h"
#include "codec/common/transform_type_contexts.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/decoder/intra_syntax_reader.h"
#include "codec/decoder/range_decoder.h"
#include "codec/encoder/forward_transform.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/intra_syntax_writer.h"
#include "codec/encoder/range_encoder.h"
#include "support/random_coefficients.h"

namespace svc::codec {
namespace {

constexpr TransformSize kSizes[] = {TransformSize::k4x4,  TransformSize::k8x8,  TransformSize::k16x16,
                                    TransformSize::k16x8, TransformSize::k8x16, TransformSize::k16x4,
                                    TransformSize::k4x16, TransformSize::k8x4,  TransformSize::k4x8};
constexpr TransformType kTypes[] = {TransformType::kDctDct, TransformType::kDctDst, TransformType::kDstDct,
                                    TransformType::kDstDst};

template <int N>
void expect_dst_matrix_rounds_the_formula(const dsp::TypeMatrix<N>& matrix) {
  const double scale = 256.0 * std::sqrt(static_cast<double>(N)) * std::sqrt(4.0 / (2 * N + 1));
  for (int k = 0; k < N; ++k) {
    for (int n = 0; n < N; ++n) {
      const double exact = scale * std::sin(std::numbers::pi * (2 * k + 1) * (n + 1) / (2 * N + 1));
      EXPECT_EQ(matrix.m[k][n], static_cast<int>(std::lround(exact))) << "N " << N << ", k " << k << ", n " << n;
    }
  }
}

TEST(TransformTypes, DstMatricesRoundTheDstViiBasis) {
  expect_dst_matrix_rounds_the_formula(dsp::kTypeDst4);
  expect_dst_matrix_rounds_the_formula(dsp::kTypeDst8);
  expect_dst_matrix_rounds_the_formula(dsp::kTypeDst16);
  // Four times HEVC's 4x4 DST, rounded at that scale.
  EXPECT_EQ(dsp::kTypeDst4.m[0][0], 117);
  EXPECT_EQ(dsp::kTypeDst4.m[1][3], -296);
  EXPECT_EQ(dsp::kTypeDst4.m[3][1], -336);
}

using testing::random_coefficients;

TEST(TransformTypes, IntegerInversesMatchTheirMatrixProductsBitExactly) {
  std::mt19937 rng(21);
  for (TransformSize size : kSizes) {
    const int area = transform_area(size);
    for (TransformType type : kTypes) {
      for (int n = 0; n < 300; ++n) {
        const auto coefficients = random_coefficients(rng, area);
        std::vector<int16_t> fast(static_cast<size_t>(area)), reference(static_cast<size_t>(area));
        inverse_transform(size, type, coefficients.data(), fast.data());
        inverse_transform_integer_reference(size, type, coefficients.data(), reference.data());
        ASSERT_EQ(fast, reference) << "size " << transform_width(size) << "x" << transform_height(size) << ", type "
                                   << static_cast<int>(type);
      }
    }
  }
}

// Residual-like blocks through the float forward transform, rounded to integer
// coefficients, then the integer inverse: the samples come back within about the
// rounding error of the size's DCT (DCT_DCT, measured first).
TEST(TransformTypes, ForwardThenInverseIsNearIdentityForEveryTypeAndSize) {
  std::mt19937 rng(22);
  for (TransformSize size : kSizes) {
    const int area = transform_area(size);
    int dct_peak = 0;
    double dct_mean_square = 0;
    for (TransformType type : kTypes) {
      int peak = 0;
      double squared = 0;
      for (int n = 0; n < 500; ++n) {
        std::vector<float> samples(static_cast<size_t>(area)), coefficients(static_cast<size_t>(area));
        const int range = n % 2 ? 255 : 20;
        for (float& s : samples) s = static_cast<float>(static_cast<int>(rng() % (2 * range + 1)) - range);
        forward_transform(size, type, samples.data(), coefficients.data());
        std::vector<int16_t> rounded(static_cast<size_t>(area)), out(static_cast<size_t>(area));
        for (int i = 0; i < area; ++i) {
          rounded[static_cast<size_t>(i)] =
              static_cast<int16_t>(std::clamp(std::lround(coefficients[static_cast<size_t>(i)]),
                                              long{kMinCoefficient}, long{kMaxCoefficient}));
        }
        inverse_transform(size, type, rounded.data(), out.data());
        for (int i = 0; i < area; ++i) {
          const double error = out[static_cast<size_t>(i)] - samples[static_cast<size_t>(i)];
          peak = std::max(peak, static_cast<int>(std::fabs(error)));
          squared += error * error;
        }
      }
      const double mean_square = squared / (500.0 * area);
      if (type == TransformType::kDctDct) {
        dct_peak = peak;
        dct_mean_square = mean_square;
      }
      EXPECT_LE(peak, dct_peak + 1) << "size " << transform_width(size) << "x" << transform_height(size)
                                    << ", type " << static_cast<int>(type);
      EXPECT_LT(mean_square, 2 * dct_mean_square + 0.05)
          << "size " << transform_width(size) << "x" << transform_height(size) << ", type "
          << static_cast<int>(type);
    }
  }
}

// The same energy for every type: quantization needs no per-type scale.
TEST(TransformTypes, EveryTypeKeepsTheScaleOfItsSize) {
  std::mt19937 rng(23);
  for (TransformSize size : kSizes) {
    const int area = transform_area(size);
    const double expected_gain = size == TransformSize::k16x16 ? 0.25
                                 : is_rectangular(size)        ? std::pow(2.0, rectangular_scale_log_sqrt2(size))
                                                               : 1.0;
    std::vector<float> samples(static_cast<size_t>(area)), coefficients(static_cast<size_t>(area));
    for (float& s : samples) s = static_cast<float>(static_cast<int>(rng() % 201) - 100);
    double sample_energy = 0;
    for (float s : samples) sample_energy += s * s;
    for (TransformType type : kTypes) {
      forward_transform(size, type, samples.data(), coefficients.data());
      double energy = 0;
      for (float c : coefficients) energy += c * c;
      EXPECT_NEAR(energy / sample_energy, expected_gain, 0.02 * expected_gain)
          << "size " << transform_width(size) << "x" << transform_height(size) << ", type "
          << static_cast<int>(type);
    }
  }
}

TEST(TransformTypes, TypesRoundTripThroughTheirContextsAndCostNothingWhenDisabled) {
  std::mt19937 rng(24);
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  TransformTypeContexts encoding;
  encoding.enabled = true;
  std::vector<std::array<int, 3>> symbols;  // size, mode, type
  for (int n = 0; n < 400; ++n) {
    const int size = static_cast<int>(rng() % kTransformSizes), mode = static_cast<int>(rng() % 36);
    const int type = static_cast<int>(rng() % 7 % kTransformTypes);
    EXPECT_GT(transform_type_bits(encoding, static_cast<TransformSize>(size), mode,
                                  static_cast<TransformType>(type)),
              0.0f);
    encode_transform_type(encoder, encoding, static_cast<TransformSize>(size), mode,
                          static_cast<TransformType>(type));
    symbols.push_back({size, mode, type});
  }
  encoder.finish();
  RangeDecoder decoder(bytes);
  TransformTypeContexts decoding;
  decoding.enabled = true;
  for (const auto& [size, mode, type] : symbols) {
    ASSERT_EQ(static_cast<int>(decode_transform_type(decoder, decoding, static_cast<TransformSize>(size), mode)),
              type);
  }
  // Disabled: nothing written, DCT_DCT read, no bits counted.
  std::vector<uint8_t> empty, disabled_bytes;
  RangeEncoder plain(&empty), disabled(&disabled_bytes);
  TransformTypeContexts off;
  for (int n = 0; n < 50; ++n) {
    encode_transform_type(disabled, off, TransformSize::k8x8, n % 35, TransformType::kDstDst);
    EXPECT_EQ(transform_type_bits(off, TransformSize::k8x8, n % 35, TransformType::kDstDst), 0.0f);
  }
  plain.finish();
  disabled.finish();
  EXPECT_EQ(disabled_bytes, empty);
  RangeDecoder off_decoder(disabled_bytes);
  EXPECT_EQ(decode_transform_type(off_decoder, off, TransformSize::k4x4, 10), TransformType::kDctDct);
  // Every size codes types, rectangular blocks too (intra syntax 13).
  for (int size = 0; size < kTransformSizes; ++size)
    EXPECT_GT(transform_type_bits(encoding, static_cast<TransformSize>(size), 10, TransformType::kDstDst), 0.0f);
}

TEST(TransformTypes, ModeClassesFollowThePredictionDirection) {
  EXPECT_EQ(transform_type_mode_class(0), 0);   // planar
  EXPECT_EQ(transform_type_mode_class(1), 0);   // DC
  EXPECT_EQ(transform_type_mode_class(10), 1);  // horizontal
  EXPECT_EQ(transform_type_mode_class(26), 2);  // vertical
  EXPECT_EQ(transform_type_mode_class(18), 3);  // diagonal
  EXPECT_EQ(transform_type_mode_class(2), 3);
  EXPECT_EQ(transform_type_mode_class(34), 3);
  EXPECT_EQ(transform_type_mode_class(35), 4);  // CfL
}

// Textured image with edges in several directions: smooth ramps that directional
// prediction leaves growing residuals in, plus noise.
ImageYCbCr420 textured_image(int width, int height) {
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  std::mt19937 rng(25);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double ramp = (x / 16 + y / 16) % 2 ? 2.5 * (x % 16) + 1.5 * (y % 16) : 3.0 * (y % 16);
      const double value = 70 + ramp + 30 * std::sin(0.21 * x + 0.13 * y) + static_cast<int>(rng() % 13);
      image.y.push_back(static_cast<uint8_t>(std::clamp(value, 0.0, 255.0)));
    }
  }
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      image.cb.push_back(static_cast<uint8_t>(100 + 2 * (x % 8) + static_cast<int>(rng() % 9)));
      image.cr.push_back(static_cast<uint8_t>(150 - 3 * (y % 8) + static_cast<int>(rng() % 9)));
    }
  }
  return image;
}

// The transform type of every block with levels, from the semi-decoded form.
std::array<int, kTransformTypes> count_types(const CoefficientFrame& frame) {
  std::array<int, kTransformTypes> counts{};
  size_t offset = 0;
  int positions[kMaxTransformArea], values[kMaxTransformArea];
  // Blocks of every size read alike here: the type precedes the levels, and reading a
  // block's levels as 16x16 consumes exactly its bytes.
  for (uint16_t count : frame.block_counts) {
    if (count == 0) continue;
    TransformType type = TransformType::kDctDct;
    frame.read_levels(&offset, count, TransformSize::k16x16, positions, values, &type);
    ++counts[static_cast<size_t>(type)];
  }
  return counts;
}

TEST(TransformTypes, IntraFramesUseEveryTypeAndDecodeExactly) {
  const ImageYCbCr420 image = textured_image(128, 96);
  for (bool types : {true, false}) {
    CodingParams params;
    params.qindex = 50;
    params.transform_types = types;
    ImageYCbCr420 reconstruction, decoded;
    const auto bytes = encode_intra_frame(image, params, &reconstruction);
    ASSERT_GT(bytes.size(), static_cast<size_t>(kFrameHeaderBytes));
    EXPECT_EQ((bytes[kIntraFlagsByte] & kTransformTypesFlag) != 0, types);
    CoefficientFrame parsed;
    ASSERT_TRUE(parse_intra_frame(bytes, image.width, image.height, &parsed).ok());
    reconstruct_intra_frame(parsed, &decoded);
    EXPECT_TRUE(decoded.y == reconstruction.y && decoded.cb == reconstruction.cb &&
                decoded.cr == reconstruction.cr);
    const auto counts = count_types(parsed);
    if (types) {
      for (int t = 0; t < kTransformTypes; ++t) EXPECT_GT(counts[static_cast<size_t>(t)], 0) << "type " << t;
    } else {
      EXPECT_EQ(counts[1] + counts[2] + counts[3], 0);
    }
  }
}

// 16x8 and 8x16 blocks choose their types too (intra syntax 13): the luma blocks of every
// macroblock in coding order, each block's type read from the semi-decoded form.
TEST(TransformTypes, RectangularBlocksUseTypes) {
  const ImageYCbCr420 image = textured_image(128, 96);
  CodingParams params;
  params.qindex = 50;
  params.transform_types = true;
  ImageYCbCr420 reconstruction, decoded;
  const auto bytes = encode_intra_frame(image, params, &reconstruction);
  CoefficientFrame parsed;
  ASSERT_TRUE(parse_intra_frame(bytes, image.width, image.height, &parsed).ok());
  reconstruct_intra_frame(parsed, &decoded);
  EXPECT_TRUE(decoded.y == reconstruction.y);
  std::array<int, kTransformTypes> rectangular{};
  size_t block = 0, offset = 0;
  int positions[kMaxTransformArea], values[kMaxTransformArea];
  for (uint16_t partition : parsed.luma_partitions) {
    intra::for_each_luma_block(partition, [&](int, int, TransformSize size) {
      const int count = parsed.block_counts[block++];
      if (count == 0) return;
      TransformType type = TransformType::kDctDct;
      ASSERT_EQ(parsed.read_levels(&offset, count, size, positions, values, &type), count);
      if (is_rectangular(size)) ++rectangular[static_cast<size_t>(type)];
    });
  }
  EXPECT_GT(rectangular[0], 0);
  EXPECT_GT(rectangular[1] + rectangular[2] + rectangular[3], 0);
}

// A stream coded without types, its header flag set: the parser then reads type bits
// the encoder never wrote, so it either fails or decodes other pixels; never a crash.
// Random damage to a stream with types likewise returns an error or some frame.
TEST(TransformTypes, DamagedStreamsGiveErrorsNotCrashes) {
  const ImageYCbCr420 image = textured_image(64, 48);
  CodingParams params;
  params.qindex = 60;
  params.transform_types = false;
  ImageYCbCr420 reconstruction;
  auto bytes = encode_intra_frame(image, params, &reconstruction);
  bytes[kIntraFlagsByte] |= kTransformTypesFlag;
  CoefficientFrame parsed;
  ImageYCbCr420 decoded;
  if (parse_intra_frame(bytes, image.width, image.height, &parsed).ok()) {
    reconstruct_intra_frame(parsed, &decoded);
    EXPECT_NE(decoded.y, reconstruction.y);
  }
  params.transform_types = true;
  const auto good = encode_intra_frame(image, params, nullptr);
  std::mt19937 rng(26);
  for (int trial = 0; trial < 300; ++trial) {
    auto damaged = good;
    for (int k = 0; k < 3; ++k) {
      const size_t at = kFrameHeaderBytes + rng() % (damaged.size() - kFrameHeaderBytes);
      damaged[at] = static_cast<uint8_t>(rng());
    }
    if (trial % 10 == 0) damaged.resize(damaged.size() / 2);
    CoefficientFrame damaged_parse;
    if (parse_intra_frame(damaged, image.width, image.height, &damaged_parse).ok()) {
      reconstruct_intra_frame(damaged_parse, &decoded);
      EXPECT_EQ(decoded.y.size(), image.y.size());
    }
  }
}

}  // namespace
}  // namespace svc::codec
