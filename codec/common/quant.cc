// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/quant.h"

#include <algorithm>
#include <cstdlib>

#include "codec/common/dct.h"
#include "codec/common/dsp/dsp.h"

namespace svc::codec {

const std::array<uint8_t, 64> kDefaultIntraMatrix = {
    8,  16, 19, 22, 26, 27, 29, 34,  //
    16, 16, 22, 24, 27, 29, 34, 37,  //
    19, 22, 26, 27, 29, 34, 34, 38,  //
    22, 22, 26, 27, 29, 34, 37, 40,  //
    22, 26, 27, 29, 32, 35, 40, 48,  //
    26, 27, 29, 32, 35, 40, 48, 58,  //
    26, 27, 29, 34, 38, 46, 56, 69,  //
    27, 29, 35, 38, 46, 56, 69, 83,  //
};

namespace {

// round(128 * 2^(k / 32)): one octave of quantizer scales.
constexpr std::array<int, kQIndexPerOctave> kScaleOctave = {
    128, 131, 134, 137, 140, 143, 146, 149, 152, 156, 159, 162, 166, 170, 173, 177,  //
    181, 185, 189, 193, 197, 202, 206, 211, 215, 220, 225, 230, 235, 240, 245, 251,  //
};

}  // namespace

int quantizer_scale_q8(int qindex) {
  qindex = std::clamp(qindex, kMinQIndex, kMaxQIndex);
  return kScaleOctave[qindex % kQIndexPerOctave] << (qindex / kQIndexPerOctave);
}

int residual_step(TransformSize size, int qindex) {
  constexpr int kNonIntraWeight = 16;  // MPEG-2's default non-intra matrix: flat
  const int step = (kNonIntraWeight * quantizer_scale_q8(qindex) + 8) >> 4;
  if (size == TransformSize::k16x16) return std::max((step + 1) >> 1, 128);
  if (is_rectangular(size)) {  // coefficients at 1/sqrt(2), 1 or sqrt(2) of orthonormal
    const int scale = rectangular_scale_log_sqrt2(size);
    if (scale < 0) return std::max((step * 181 + 128) >> 8, 128);
    if (scale > 0) return (step * 362 + 128) >> 8;
  }
  return step;
}

int residual_weight(TransformSize size, int position) {
  const int width = transform_width(size), height = transform_height(size);
  const int row = position / width, column = position % width;
  const int r = row * 8 / height, c = column * 8 / width;  // the 8x8 entry standing for the same frequency
  return r == 0 && c == 0 ? 16 : kDefaultIntraMatrix[static_cast<size_t>(8 * r + c)];
}

int residual_step(TransformSize size, int qindex, ResidualMatrix matrix, int position) {
  const int step = residual_step(size, qindex);
  if (matrix == ResidualMatrix::kFlat) return step;
  return std::max((step * residual_weight(size, position) + 8) >> 4, 128);
}

Quantizer make_residual_quantizer(TransformSize size, int qindex, ResidualMatrix matrix) {
  Quantizer q;
  q.qindex = std::clamp(qindex, kMinQIndex, kMaxQIndex);
  q.size = size;
  q.rounding_dc = 0.2f;  // residuals: wider dead zone, most blocks become empty
  q.rounding_ac = 0.2f;
  // The 8x8 kernels read 64 entries: past a smaller block they hold the flat 8x8 step.
  for (int i = 0; i < 64; ++i) {
    q.scale[static_cast<size_t>(i)] = residual_step(TransformSize::k8x8, q.qindex);
    q.inverse_step[static_cast<size_t>(i)] =
        static_cast<float>(1 << kStepBits) / static_cast<float>(q.scale[static_cast<size_t>(i)]);
  }
  for (int i = 0; i < transform_area(size); ++i) {
    q.scale[static_cast<size_t>(i)] = residual_step(size, q.qindex, matrix, i);
    q.inverse_step[static_cast<size_t>(i)] =
        static_cast<float>(1 << kStepBits) / static_cast<float>(q.scale[static_cast<size_t>(i)]);
  }
  return q;
}

// The 8x8 kernel serves every size: areas of 64 and more as runs of 64 values, smaller
// ones (4x4, 8x4, 4x8) padded with zeros to 64, so that nothing past the block is read
// or written.
void dequantize_block(const Quantizer& quantizer, const int16_t* levels, int16_t* coefficients) {
  const dsp::DspTable& dsp = dsp::get_dsp();
  const int area = transform_area(quantizer.size);
  if (area < 64) {
    int16_t padded[64] = {}, padded_coefficients[64];
    std::copy_n(levels, area, padded);
    dsp.dequantize_8x8(padded, quantizer.scale.data(), padded_coefficients);
    std::copy_n(padded_coefficients, area, coefficients);
    return;
  }
  for (int i = 0; i < area; i += 64) dsp.dequantize_8x8(levels + i, quantizer.scale.data() + i, coefficients + i);
}

void dequantize_inverse_transform_block(const Quantizer& quantizer, const int16_t* levels, int16_t* samples) {
  int16_t coefficients[kMaxTransformArea];
  dequantize_block(quantizer, levels, coefficients);
  inverse_transform(quantizer.size, coefficients, samples);
}

}  // namespace svc::codec
