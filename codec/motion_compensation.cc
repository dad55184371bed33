#include "codec/motion_compensation.h"

#include <algorithm>
#include <cstdlib>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace svc::codec {
namespace {

#if defined(__SSE2__)
// (a + b + c + d + 2) >> 2 per byte, exactly: the mean of the two pair means, less the
// one that rounding twice adds (when a pair's sum and the means' sum are both odd).
inline __m128i average4_epu8(__m128i a, __m128i b, __m128i c, __m128i d) {
  const __m128i ab = _mm_avg_epu8(a, b), cd = _mm_avg_epu8(c, d);
  const __m128i odd = _mm_or_si128(_mm_xor_si128(a, b), _mm_xor_si128(c, d));
  const __m128i excess = _mm_and_si128(_mm_and_si128(odd, _mm_xor_si128(ab, cd)), _mm_set1_epi8(1));
  return _mm_sub_epi8(_mm_avg_epu8(ab, cd), excess);
}

inline __m128i load8(const uint8_t* p) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)); }
inline __m128i load16(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }

// interpolate() for blocks 8 or 16 samples wide.
template <int kWidth>
void interpolate_sse2(const uint8_t* window, int window_stride, int block_height, int fx, int fy, uint8_t* out,
                      int out_stride) {
  auto load = [](const uint8_t* p) { return kWidth == 16 ? load16(p) : load8(p); };
  for (int y = 0; y < block_height; ++y) {
    const uint8_t* row = window + static_cast<ptrdiff_t>(y) * window_stride;
    const uint8_t* below = row + window_stride;
    __m128i value;
    if (fy == 0) {
      value = fx == 0 ? load(row) : _mm_avg_epu8(load(row), load(row + 1));
    } else if (fx == 0) {
      value = _mm_avg_epu8(load(row), load(below));
    } else {
      value = average4_epu8(load(row), load(row + 1), load(below), load(below + 1));
    }
    uint8_t* dst = out + static_cast<ptrdiff_t>(y) * out_stride;
    if (kWidth == 16) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(dst), value);
    } else {
      _mm_storel_epi64(reinterpret_cast<__m128i*>(dst), value);
    }
  }
}
#endif

// Interpolates from a window whose sample (0, 0) is the integer reference position of the
// block's top-left sample; the window holds (block + 1) samples in each direction.
inline void interpolate(const uint8_t* window, int window_stride, int block_width,
                        int block_height, int fx, int fy, uint8_t* out, int out_stride) {
#if defined(__SSE2__)
  // Macroblock luma and chroma widths; the loops below are the plain definition.
  if (block_width == 16) return interpolate_sse2<16>(window, window_stride, block_height, fx, fy, out, out_stride);
  if (block_width == 8) return interpolate_sse2<8>(window, window_stride, block_height, fx, fy, out, out_stride);
#endif
  if (fx == 0 && fy == 0) {
    for (int y = 0; y < block_height; ++y) {
      std::copy_n(window + static_cast<ptrdiff_t>(y) * window_stride, block_width,
                  out + static_cast<ptrdiff_t>(y) * out_stride);
    }
  } else if (fy == 0) {
    for (int y = 0; y < block_height; ++y) {
      const uint8_t* row = window + static_cast<ptrdiff_t>(y) * window_stride;
      uint8_t* dst = out + static_cast<ptrdiff_t>(y) * out_stride;
      for (int x = 0; x < block_width; ++x) dst[x] = static_cast<uint8_t>((row[x] + row[x + 1] + 1) >> 1);
    }
  } else if (fx == 0) {
    for (int y = 0; y < block_height; ++y) {
      const uint8_t* row = window + static_cast<ptrdiff_t>(y) * window_stride;
      const uint8_t* below = row + window_stride;
      uint8_t* dst = out + static_cast<ptrdiff_t>(y) * out_stride;
      for (int x = 0; x < block_width; ++x) dst[x] = static_cast<uint8_t>((row[x] + below[x] + 1) >> 1);
    }
  } else {
    for (int y = 0; y < block_height; ++y) {
      const uint8_t* row = window + static_cast<ptrdiff_t>(y) * window_stride;
      const uint8_t* below = row + window_stride;
      uint8_t* dst = out + static_cast<ptrdiff_t>(y) * out_stride;
      for (int x = 0; x < block_width; ++x) {
        dst[x] = static_cast<uint8_t>((row[x] + row[x + 1] + below[x] + below[x + 1] + 2) >> 2);
      }
    }
  }
}

}  // namespace

int max_vector_component(int width, int height) {
  const long long limit = 2LL * std::max(width, height) + 64;
  return static_cast<int>(std::min<long long>(limit, 32767));
}

bool vector_in_range(MotionVector vector, int width, int height) {
  const int limit = max_vector_component(width, height);
  return std::abs(vector.x) <= limit && std::abs(vector.y) <= limit;
}

void predict_block(const uint8_t* plane, int plane_width, int plane_height, int x0, int y0,
                   int block_width, int block_height, int vector_x, int vector_y, uint8_t* out,
                   int out_stride) {
  if (block_width > kMaxPredictionBlock || block_height > kMaxPredictionBlock) {
    predict_block_reference(plane, plane_width, plane_height, x0, y0, block_width, block_height,
                            vector_x, vector_y, out, out_stride);
    return;
  }
  const int full_x = 2 * x0 + vector_x, full_y = 2 * y0 + vector_y;
  const int ix = full_x >> 1, iy = full_y >> 1;
  const int fx = full_x & 1, fy = full_y & 1;
  // The window read by interpolate: one extra column/row only where interpolating.
  const int need_w = block_width + fx, need_h = block_height + fy;
  if (ix >= 0 && iy >= 0 && ix + need_w <= plane_width && iy + need_h <= plane_height) {
    interpolate(plane + static_cast<ptrdiff_t>(iy) * plane_width + ix, plane_width, block_width,
                block_height, fx, fy, out, out_stride);
    return;
  }
  // Partly or wholly outside: gather an edge-extended window first.
  uint8_t window[(kMaxPredictionBlock + 1) * (kMaxPredictionBlock + 1)];
  const int window_stride = kMaxPredictionBlock + 1;
  int columns[kMaxPredictionBlock + 1];
  for (int x = 0; x < need_w; ++x) columns[x] = std::clamp(ix + x, 0, plane_width - 1);
  for (int y = 0; y < need_h; ++y) {
    const uint8_t* row =
        plane + static_cast<ptrdiff_t>(std::clamp(iy + y, 0, plane_height - 1)) * plane_width;
    uint8_t* dst = window + y * window_stride;
    for (int x = 0; x < need_w; ++x) dst[x] = row[columns[x]];
  }
  interpolate(window, window_stride, block_width, block_height, fx, fy, out, out_stride);
}

void predict_block_reference(const uint8_t* plane, int plane_width, int plane_height, int x0,
                             int y0, int block_width, int block_height, int vector_x,
                             int vector_y, uint8_t* out, int out_stride) {
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

void predict_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y,
                             MotionVector vector, uint8_t* out) {
  predict_block(reference.y.data(), reference.width, reference.height, mb_x * 16, mb_y * 16, 16, 16,
                vector.x, vector.y, out, 16);
}

void average_samples(const uint8_t* a, const uint8_t* b, int count, uint8_t* out) {
  for (int i = 0; i < count; ++i) out[i] = static_cast<uint8_t>((a[i] + b[i] + 1) >> 1);
}

void average_predictions(const MacroblockPrediction& a, const MacroblockPrediction& b,
                         MacroblockPrediction* out) {
  average_samples(a.y.data(), b.y.data(), 256, out->y.data());
  average_samples(a.cb.data(), b.cb.data(), 64, out->cb.data());
  average_samples(a.cr.data(), b.cr.data(), 64, out->cr.data());
}

int sad_16x16(const uint8_t* source, int source_stride, const uint8_t* prediction) {
#if defined(__SSE2__)
  __m128i sum = _mm_setzero_si128();
  for (int y = 0; y < 16; ++y) {
    sum = _mm_add_epi64(sum, _mm_sad_epu8(load16(source + static_cast<ptrdiff_t>(y) * source_stride),
                                          load16(prediction + 16 * y)));
  }
  return _mm_cvtsi128_si32(sum) + _mm_cvtsi128_si32(_mm_srli_si128(sum, 8));
#else
  return sad_16x16_reference(source, source_stride, prediction);
#endif
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
  // Inside the plane: interpolate row by row and stop once the limit is passed.
  const uint8_t* base = reference.y.data() + static_cast<ptrdiff_t>(iy) * width + ix;
#if defined(__SSE2__)
  // Same arithmetic with SSE2: pavgb is exactly (a + b + 1) >> 1, average4_epu8 the
  // 4-tap case.
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const uint8_t* row = base + static_cast<ptrdiff_t>(y) * width;
    const __m128i src = load16(source + static_cast<ptrdiff_t>(y) * source_stride);
    const __m128i a = load16(row);
    __m128i prediction;
    if (fx == 0 && fy == 0) {
      prediction = a;
    } else if (fy == 0) {
      prediction = _mm_avg_epu8(a, load16(row + 1));
    } else if (fx == 0) {
      prediction = _mm_avg_epu8(a, load16(row + width));
    } else {
      prediction = average4_epu8(a, load16(row + 1), load16(row + width), load16(row + width + 1));
    }
    const __m128i sad = _mm_sad_epu8(src, prediction);
    sum += _mm_cvtsi128_si32(sad) + _mm_cvtsi128_si32(_mm_srli_si128(sad, 8));
    if (sum > limit) return sum;
  }
  return sum;
#else
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const uint8_t* row = base + static_cast<ptrdiff_t>(y) * width;
    const uint8_t* below = row + width;
    const uint8_t* src = source + static_cast<ptrdiff_t>(y) * source_stride;
    int row_sum = 0;
    if (fx == 0 && fy == 0) {
      for (int x = 0; x < 16; ++x) row_sum += std::abs(src[x] - row[x]);
    } else if (fy == 0) {
      for (int x = 0; x < 16; ++x) row_sum += std::abs(src[x] - ((row[x] + row[x + 1] + 1) >> 1));
    } else if (fx == 0) {
      for (int x = 0; x < 16; ++x) row_sum += std::abs(src[x] - ((row[x] + below[x] + 1) >> 1));
    } else {
      for (int x = 0; x < 16; ++x) {
        row_sum += std::abs(src[x] - ((row[x] + row[x + 1] + below[x] + below[x + 1] + 2) >> 2));
      }
    }
    sum += row_sum;
    if (sum > limit) return sum;
  }
  return sum;
#endif
}

}  // namespace svc::codec
