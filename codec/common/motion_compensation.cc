// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/motion_compensation.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "codec/common/dsp/dsp.h"

namespace svc::codec {
namespace {

// HEVC's DCT-based interpolation filters (luma 8 taps, chroma 4 taps centred in 8).
constexpr std::array<std::array<int8_t, 8>, 4> kLumaTaps = {{
    {0, 0, 0, 64, 0, 0, 0, 0},
    {-1, 4, -10, 58, 17, -5, 1, 0},
    {-1, 4, -11, 40, 40, -11, 4, -1},
    {0, 1, -5, 17, 58, -10, 4, -1},
}};
constexpr std::array<std::array<int8_t, 8>, 8> kChromaTaps = {{
    {0, 0, 0, 64, 0, 0, 0, 0},
    {0, 0, -2, 58, 10, -2, 0, 0},
    {0, 0, -4, 54, 16, -2, 0, 0},
    {0, 0, -6, 46, 28, -4, 0, 0},
    {0, 0, -4, 36, 36, -4, 0, 0},
    {0, 0, -4, 28, 46, -6, 0, 0},
    {0, 0, -2, 16, 54, -4, 0, 0},
    {0, 0, -2, 10, 58, -2, 0, 0},
}};

// AV1's EIGHTTAP_SMOOTH (av1_sub_pel_filters_8smooth) halved to a sum of 64: its 1/16
// phases 4, 8, 12 for luma and 2, 4, .., 14 for chroma.
constexpr std::array<std::array<int8_t, 8>, 4> kSmoothLumaTaps = {{
    {0, 0, 0, 64, 0, 0, 0, 0},
    {0, 0, 10, 30, 21, 3, 0, 0},
    {0, -1, 7, 26, 26, 7, -1, 0},
    {0, 0, 3, 21, 30, 10, 0, 0},
}};
constexpr std::array<std::array<int8_t, 8>, 8> kSmoothChromaTaps = {{
    {0, 0, 0, 64, 0, 0, 0, 0},
    {0, 0, 13, 31, 18, 2, 0, 0},
    {0, 0, 10, 30, 21, 3, 0, 0},
    {0, 0, 8, 28, 23, 5, 0, 0},
    {0, -1, 7, 26, 26, 7, -1, 0},
    {0, 0, 5, 23, 28, 8, 0, 0},
    {0, 0, 3, 21, 30, 10, 0, 0},
    {0, 0, 2, 18, 31, 13, 0, 0},
}};
// Bilinear between the samples at offsets 0 and 1.
constexpr std::array<std::array<int8_t, 8>, 4> kBilinearLumaTaps = {{
    {0, 0, 0, 64, 0, 0, 0, 0},
    {0, 0, 0, 48, 16, 0, 0, 0},
    {0, 0, 0, 32, 32, 0, 0, 0},
    {0, 0, 0, 16, 48, 0, 0, 0},
}};
constexpr std::array<std::array<int8_t, 8>, 8> kBilinearChromaTaps = {{
    {0, 0, 0, 64, 0, 0, 0, 0},
    {0, 0, 0, 56, 8, 0, 0, 0},
    {0, 0, 0, 48, 16, 0, 0, 0},
    {0, 0, 0, 40, 24, 0, 0, 0},
    {0, 0, 0, 32, 32, 0, 0, 0},
    {0, 0, 0, 24, 40, 0, 0, 0},
    {0, 0, 0, 16, 48, 0, 0, 0},
    {0, 0, 0, 8, 56, 0, 0, 0},
}};

// The 8 taps reach 3 samples before and 4 after the integer position.
constexpr int kTapsBefore = 3, kTapExtent = 7;
// Window rows are read up to 8 samples past the taps' reach (dsp.h).
constexpr int kWindowStride = kMaxPredictionBlock + kTapExtent + 8;

int fraction_bits(PlaneKind kind) { return kind == PlaneKind::kLuma ? 2 : 3; }

// Copies the samples a block's taps read, (width + 7) x (height + 7) from (left, top),
// with every coordinate clamped to the plane: the one place edge extension happens.
void fetch_window(const uint8_t* plane, int plane_width, int plane_height, int left, int top, int width, int height,
                  uint8_t* window) {
  const bool inside_x = left >= 0 && left + width <= plane_width;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = plane + static_cast<ptrdiff_t>(std::clamp(top + y, 0, plane_height - 1)) * plane_width;
    uint8_t* dst = window + y * kWindowStride;
    if (inside_x) {
      std::memcpy(dst, row + left, static_cast<size_t>(width));
    } else {
      for (int x = 0; x < width; ++x) dst[x] = row[std::clamp(left + x, 0, plane_width - 1)];
    }
  }
}

}  // namespace

int max_vector_component(int width, int height) {
  const long long limit = 4LL * std::max(width, height) + 128;
  return static_cast<int>(std::min<long long>(limit, 32767));
}

bool vector_in_range(MotionVector vector, int width, int height) {
  const int limit = max_vector_component(width, height);
  return std::abs(vector.x) <= limit && std::abs(vector.y) <= limit;
}

const std::array<int8_t, 8>& interpolation_taps(PlaneKind kind, int phase, InterpolationFilter filter) {
  const bool luma = kind == PlaneKind::kLuma;
  const auto index = static_cast<size_t>(phase & (luma ? 3 : 7));
  switch (filter) {
    case InterpolationFilter::kSmooth: return luma ? kSmoothLumaTaps[index] : kSmoothChromaTaps[index];
    case InterpolationFilter::kBilinear: return luma ? kBilinearLumaTaps[index] : kBilinearChromaTaps[index];
    case InterpolationFilter::kRegular: break;
  }
  return luma ? kLumaTaps[index] : kChromaTaps[index];
}

ReadWindow prediction_window(PlaneKind kind, int x0, int y0, int block_width, int block_height, int vector_x,
                             int vector_y) {
  const int bits = fraction_bits(kind);
  const int left = (((x0 << bits) + vector_x) >> bits) - kTapsBefore;
  const int top = (((y0 << bits) + vector_y) >> bits) - kTapsBefore;
  return {left, top, left + block_width - 1 + kTapExtent, top + block_height - 1 + kTapExtent};
}

void predict_block(const uint8_t* plane, int plane_width, int plane_height, PlaneKind kind, int x0, int y0,
                   int block_width, int block_height, int vector_x, int vector_y, int16_t* out, int out_stride,
                   InterpolationFilter filter) {
  if (block_width > kMaxPredictionBlock || block_height > kMaxPredictionBlock || block_width % 4 != 0) {
    predict_block_reference(plane, plane_width, plane_height, kind, x0, y0, block_width, block_height, vector_x,
                            vector_y, out, out_stride, filter);
    return;
  }
  const int bits = fraction_bits(kind), mask = (1 << bits) - 1;
  const int full_x = (x0 << bits) + vector_x, full_y = (y0 << bits) + vector_y;
  const int left = (full_x >> bits) - kTapsBefore, top = (full_y >> bits) - kTapsBefore;
  const int8_t* h_taps = interpolation_taps(kind, full_x & mask, filter).data();
  const int8_t* v_taps = interpolation_taps(kind, full_y & mask, filter).data();
  // Wholly inside the plane, the taps read it in place: no edge to extend. Kernels read
  // rows past the taps' reach (dsp.h: 1 sample for widths of whole 8-sample groups, up to
  // 8 otherwise), which must lie in the same row.
  const int over_read = block_width % 8 == 0 ? 1 : 8;
  if (left >= 0 && top >= 0 && left + block_width + kTapExtent + over_read <= plane_width &&
      top + block_height + kTapExtent <= plane_height) {
    dsp::get_dsp().interpolate_8tap(plane + static_cast<ptrdiff_t>(top) * plane_width + left, plane_width,
                                    block_width, block_height, h_taps, v_taps, out, out_stride);
    return;
  }
  uint8_t window[(kMaxPredictionBlock + kTapExtent) * kWindowStride];
  fetch_window(plane, plane_width, plane_height, left, top, block_width + kTapExtent, block_height + kTapExtent,
               window);
  dsp::get_dsp().interpolate_8tap(window, kWindowStride, block_width, block_height, h_taps, v_taps, out,
                                  out_stride);
}

void predict_block_reference(const uint8_t* plane, int plane_width, int plane_height, PlaneKind kind, int x0,
                             int y0, int block_width, int block_height, int vector_x, int vector_y, int16_t* out,
                             int out_stride, InterpolationFilter filter) {
  auto sample = [&](long long u, long long v) -> long long {
    const long long cu = std::clamp<long long>(u, 0, plane_width - 1);
    const long long cv = std::clamp<long long>(v, 0, plane_height - 1);
    return plane[cv * plane_width + cu];
  };
  const long long scale = 1LL << fraction_bits(kind);
  auto floor_div = [&](long long value) { return value >= 0 ? value / scale : -((-value + scale - 1) / scale); };
  for (int j = 0; j < block_height; ++j) {
    for (int i = 0; i < block_width; ++i) {
      const long long full_x = scale * (x0 + i) + vector_x, full_y = scale * (y0 + j) + vector_y;
      const long long ix = floor_div(full_x), iy = floor_div(full_y);
      const auto& h = interpolation_taps(kind, static_cast<int>(full_x - scale * ix), filter);
      const auto& v = interpolation_taps(kind, static_cast<int>(full_y - scale * iy), filter);
      long long sum = 0;
      for (int row = 0; row < 8; ++row) {
        long long across = 0;
        for (int k = 0; k < 8; ++k) across += h[static_cast<size_t>(k)] * sample(ix - 3 + k, iy - 3 + row);
        sum += v[static_cast<size_t>(row)] * across;
      }
      const long long shifted = sum >= 0 ? sum / 64 : -((-sum + 63) / 64);  // floor
      out[static_cast<ptrdiff_t>(j) * out_stride + i] = static_cast<int16_t>(shifted - kIntermediateOffset);
    }
  }
}

void predict_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        MacroblockIntermediate* out, InterpolationFilter filter) {
  predict_macroblock_luma(reference, mb_x, mb_y, vector, out->y.data(), filter);
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  predict_block(reference.cb.data(), cw, ch, PlaneKind::kChroma, mb_x * 8, mb_y * 8, 8, 8, vector.x, vector.y,
                out->cb.data(), 8, filter);
  predict_block(reference.cr.data(), cw, ch, PlaneKind::kChroma, mb_x * 8, mb_y * 8, 8, 8, vector.x, vector.y,
                out->cr.data(), 8, filter);
}

void predict_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector, int16_t* out,
                             InterpolationFilter filter) {
  predict_block(reference.y.data(), reference.width, reference.height, PlaneKind::kLuma, mb_x * 16, mb_y * 16, 16,
                16, vector.x, vector.y, out, 16, filter);
}

void round_prediction(const int16_t* in, int count, uint8_t* out) {
  dsp::get_dsp().put_intermediate(in, count, out);
}

void average_prediction(const int16_t* a, const int16_t* b, int count, uint8_t* out) {
  dsp::get_dsp().average_intermediate(a, b, count, out);
}

void finish_prediction(const MacroblockIntermediate& first, const MacroblockIntermediate* second,
                       MacroblockPrediction* out) {
  if (second == nullptr) {
    round_prediction(first.y.data(), 256, out->y.data());
    round_prediction(first.cb.data(), 64, out->cb.data());
    round_prediction(first.cr.data(), 64, out->cr.data());
    return;
  }
  average_prediction(first.y.data(), second->y.data(), 256, out->y.data());
  average_prediction(first.cb.data(), second->cb.data(), 64, out->cb.data());
  average_prediction(first.cr.data(), second->cr.data(), 64, out->cr.data());
}

}  // namespace svc::codec
