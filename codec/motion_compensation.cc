#include "codec/motion_compensation.h"

#include <algorithm>
#include <cstdlib>

#include "codec/dsp/dsp.h"

namespace svc::codec {

int max_vector_component(int width, int height) {
  const long long limit = 2LL * std::max(width, height) + 64;
  return static_cast<int>(std::min<long long>(limit, 32767));
}

bool vector_in_range(MotionVector vector, int width, int height) {
  const int limit = max_vector_component(width, height);
  return std::abs(vector.x) <= limit && std::abs(vector.y) <= limit;
}

void predict_block(const uint8_t* plane, int plane_width, int plane_height, int x0, int y0, int block_width,
                   int block_height, int vector_x, int vector_y, uint8_t* out, int out_stride) {
  if (block_width > kMaxPredictionBlock || block_height > kMaxPredictionBlock) {
    predict_block_reference(plane, plane_width, plane_height, x0, y0, block_width, block_height, vector_x, vector_y,
                            out, out_stride);
    return;
  }
  const int full_x = 2 * x0 + vector_x, full_y = 2 * y0 + vector_y;
  const int ix = full_x >> 1, iy = full_y >> 1;
  const int fx = full_x & 1, fy = full_y & 1;
  // The window read by put_half_pel: one extra column/row only where interpolating.
  const int need_w = block_width + fx, need_h = block_height + fy;
  if (ix >= 0 && iy >= 0 && ix + need_w <= plane_width && iy + need_h <= plane_height) {
    dsp::get_dsp().put_half_pel(plane + static_cast<ptrdiff_t>(iy) * plane_width + ix, plane_width, block_width,
                                block_height, fx, fy, out, out_stride);
    return;
  }
  // Partly or wholly outside: gather an edge-extended window first.
  uint8_t window[(kMaxPredictionBlock + 1) * (kMaxPredictionBlock + 1)];
  const int window_stride = kMaxPredictionBlock + 1;
  int columns[kMaxPredictionBlock + 1];
  for (int x = 0; x < need_w; ++x) columns[x] = std::clamp(ix + x, 0, plane_width - 1);
  for (int y = 0; y < need_h; ++y) {
    const uint8_t* row = plane + static_cast<ptrdiff_t>(std::clamp(iy + y, 0, plane_height - 1)) * plane_width;
    uint8_t* dst = window + y * window_stride;
    for (int x = 0; x < need_w; ++x) dst[x] = row[columns[x]];
  }
  dsp::get_dsp().put_half_pel(window, window_stride, block_width, block_height, fx, fy, out, out_stride);
}

void predict_block_reference(const uint8_t* plane, int plane_width, int plane_height, int x0, int y0,
                             int block_width, int block_height, int vector_x, int vector_y, uint8_t* out,
                             int out_stride) {
  auto sample = [&](long long u, long long v) -> int {
    const long long cu = std::clamp<long long>(u, 0, plane_width - 1);
    const long long cv = std::clamp<long long>(v, 0, plane_height - 1);
    return plane[cv * plane_width + cu];
  };
  for (int j = 0; j < block_height; ++j) {
    for (int i = 0; i < block_width; ++i) {
      const long long full_x = 2LL * (x0 + i) + vector_x, full_y = 2LL * (y0 + j) + vector_y;
      const long long px = full_x >= 0 ? full_x / 2 : -((-full_x + 1) / 2);  // floor
      const long long py = full_y >= 0 ? full_y / 2 : -((-full_y + 1) / 2);
      const bool half_x = (full_x - 2 * px) != 0, half_y = (full_y - 2 * py) != 0;
      int value;
      if (!half_x && !half_y) {
        value = sample(px, py);
      } else if (half_x && !half_y) {
        value = (sample(px, py) + sample(px + 1, py) + 1) / 2;
      } else if (!half_x && half_y) {
        value = (sample(px, py) + sample(px, py + 1) + 1) / 2;
      } else {
        value = (sample(px, py) + sample(px + 1, py) + sample(px, py + 1) + sample(px + 1, py + 1) + 2) / 4;
      }
      out[static_cast<ptrdiff_t>(j) * out_stride + i] = static_cast<uint8_t>(value);
    }
  }
}

void predict_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        MacroblockPrediction* out) {
  predict_macroblock_luma(reference, mb_x, mb_y, vector, out->y.data());
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  const MotionVector c = chroma_vector(vector);
  predict_block(reference.cb.data(), cw, ch, mb_x * 8, mb_y * 8, 8, 8, c.x, c.y, out->cb.data(), 8);
  predict_block(reference.cr.data(), cw, ch, mb_x * 8, mb_y * 8, 8, 8, c.x, c.y, out->cr.data(), 8);
}

void predict_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                             uint8_t* out) {
  predict_block(reference.y.data(), reference.width, reference.height, mb_x * 16, mb_y * 16, 16, 16, vector.x,
                vector.y, out, 16);
}

void average_samples(const uint8_t* a, const uint8_t* b, int count, uint8_t* out) {
  dsp::get_dsp().average(a, b, count, out);
}

void average_predictions(const MacroblockPrediction& a, const MacroblockPrediction& b, MacroblockPrediction* out) {
  average_samples(a.y.data(), b.y.data(), 256, out->y.data());
  average_samples(a.cb.data(), b.cb.data(), 64, out->cb.data());
  average_samples(a.cr.data(), b.cr.data(), 64, out->cr.data());
}

int sad_16x16(const uint8_t* source, int source_stride, const uint8_t* prediction) {
  return dsp::get_dsp().sad_16x16(source, source_stride, prediction);
}

int sad_16x16_reference(const uint8_t* source, int source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const uint8_t* row = source + static_cast<ptrdiff_t>(y) * source_stride;
    const uint8_t* pred = prediction + 16 * y;
    int row_sum = 0;
    for (int x = 0; x < 16; ++x) row_sum += std::abs(static_cast<int>(row[x]) - static_cast<int>(pred[x]));
    sum += row_sum;
  }
  return sum;
}

int sad_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        const uint8_t* source, int source_stride, int limit) {
  const int width = reference.width, height = reference.height;
  const int full_x = 32 * mb_x + vector.x, full_y = 32 * mb_y + vector.y;
  const int ix = full_x >> 1, iy = full_y >> 1, fx = full_x & 1, fy = full_y & 1;
  if (ix < 0 || iy < 0 || ix + 16 + fx > width || iy + 16 + fy > height) {
    uint8_t prediction[256];
    predict_macroblock_luma(reference, mb_x, mb_y, vector, prediction);
    return sad_16x16(source, source_stride, prediction);
  }
  // Inside the plane: the kernel interpolates row by row and stops once the limit is passed.
  const uint8_t* base = reference.y.data() + static_cast<ptrdiff_t>(iy) * width + ix;
  return dsp::get_dsp().sad_half_pel_16x16(base, width, fx, fy, source, source_stride, limit);
}

}  // namespace svc::codec
