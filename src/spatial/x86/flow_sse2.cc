// SPDX-License-Identifier: BSD-2-Clause
// SSE2 flow kernels: the plain formulas two pixels (flow, in doubles) or four pixels
// (quarter-pel keys) at a time with the same operations in the same order, so the same
// bits; comparison masks replace the branches.
#include <emmintrin.h>

#include <cstring>

#include "codec/common/dsp/x86/target.h"
#include "spatial/flow_kernels_init.h"

SVC_TARGET_BEGIN("sse2")

namespace svc {
namespace {

__m128d select_pd(__m128d mask, __m128d a, __m128d b) {
  return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b));
}

void flow_row_sse2(const FlowRow& r, const float* depth, float* dx, float* dy, uint8_t* valid) {
  const __m128d row_x = _mm_set1_pd(r.row_x), row_y = _mm_set1_pd(r.row_y), row_z = _mm_set1_pd(r.row_z);
  const __m128d t_x = _mm_set1_pd(r.shift_x), t_y = _mm_set1_pd(r.shift_y), t_z = _mm_set1_pd(r.shift_z);
  const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0), minus_one = _mm_set1_pd(-1.0);
  const __m128d half = _mm_set1_pd(0.5), far2 = _mm_set1_pd(r.far_plane);
  const __m128d inf2 = _mm_set1_pd(std::numeric_limits<double>::infinity());
  const __m128d in_front_limit = _mm_set1_pd(-kMinDepthInFront);
  const __m128d largest2 = _mm_set1_pd(std::numeric_limits<double>::max());
  const __m128d abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  const __m128d p00 = _mm_set1_pd(r.p00), p02 = _mm_set1_pd(r.p02), p11 = _mm_set1_pd(r.p11);
  const __m128d p12 = _mm_set1_pd(r.p12), w2 = _mm_set1_pd(r.width), h2 = _mm_set1_pd(r.height);
  const __m128d jj = _mm_set1_pd(static_cast<double>(r.row));
  int i = 0;
  for (; i + 2 <= r.count; i += 2) {
    const __m128d dir_x = _mm_add_pd(_mm_loadu_pd(r.column_x + i), row_x);
    const __m128d dir_y = _mm_add_pd(_mm_loadu_pd(r.column_y + i), row_y);
    const __m128d dir_z = _mm_add_pd(_mm_loadu_pd(r.column_z + i), row_z);
    const __m128d z = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(depth + i))));
    // Not background: 0 < z < far and finite (false for NaN).
    const __m128d geometry =
        _mm_and_pd(_mm_and_pd(_mm_cmpgt_pd(z, zero), _mm_cmplt_pd(z, far2)), _mm_cmplt_pd(z, inf2));
    const __m128d scale = select_pd(geometry, z, one), shift = _mm_and_pd(geometry, one);
    const __m128d px = _mm_add_pd(_mm_mul_pd(scale, dir_x), _mm_mul_pd(shift, t_x));
    const __m128d py = _mm_add_pd(_mm_mul_pd(scale, dir_y), _mm_mul_pd(shift, t_y));
    const __m128d pz = _mm_add_pd(_mm_mul_pd(scale, dir_z), _mm_mul_pd(shift, t_z));
    const __m128d in_front = _mm_cmplt_pd(pz, in_front_limit);
    const __m128d inv = _mm_div_pd(minus_one, select_pd(in_front, pz, minus_one));
    const __m128d x_ndc = _mm_sub_pd(_mm_mul_pd(_mm_mul_pd(p00, px), inv), p02);
    const __m128d y_ndc = _mm_sub_pd(_mm_mul_pd(_mm_mul_pd(p11, py), inv), p12);
    const __m128d u = _mm_sub_pd(_mm_mul_pd(_mm_mul_pd(_mm_add_pd(x_ndc, one), half), w2), half);
    const __m128d v = _mm_sub_pd(_mm_mul_pd(_mm_mul_pd(_mm_sub_pd(one, y_ndc), half), h2), half);
    const __m128d fx = _mm_sub_pd(u, _mm_set_pd(i + 1.0, static_cast<double>(i)));
    const __m128d fy = _mm_sub_pd(v, jj);
    const __m128d ok = _mm_and_pd(_mm_and_pd(in_front, _mm_cmple_pd(_mm_and_pd(fx, abs_mask), largest2)),
                                  _mm_cmple_pd(_mm_and_pd(fy, abs_mask), largest2));
    _mm_storel_pi(reinterpret_cast<__m64*>(dx + i), _mm_cvtpd_ps(_mm_and_pd(ok, fx)));
    _mm_storel_pi(reinterpret_cast<__m64*>(dy + i), _mm_cvtpd_ps(_mm_and_pd(ok, fy)));
    const int mask = _mm_movemask_pd(ok);
    valid[i] = static_cast<uint8_t>(mask & 1);
    valid[i + 1] = static_cast<uint8_t>(mask >> 1);
  }
  for (; i < r.count; ++i) flow_pixel(r, i, depth[i], &dx[i], &dy[i], &valid[i]);
}

// round_half_away four lanes at a time; *ok is -1 where the lane is in range.
__m128i round_half_away4(__m128 d, __m128 bound, __m128i limit, __m128i* ok) {
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 scaled = _mm_mul_ps(d, _mm_set1_ps(4.0f));
  const __m128 in_range = _mm_cmplt_ps(_mm_and_ps(scaled, abs_mask), bound);  // false for NaN
  const __m128 safe = _mm_and_ps(scaled, in_range);
  __m128i rounded = _mm_cvttps_epi32(safe);
  const __m128 fraction = _mm_sub_ps(safe, _mm_cvtepi32_ps(rounded));
  // Comparison masks are -1 where true.
  rounded = _mm_sub_epi32(rounded, _mm_castps_si128(_mm_cmpge_ps(fraction, _mm_set1_ps(0.5f))));
  rounded = _mm_add_epi32(rounded, _mm_castps_si128(_mm_cmple_ps(fraction, _mm_set1_ps(-0.5f))));
  const __m128i minus_limit = _mm_sub_epi32(_mm_setzero_si128(), limit);
  const __m128i beyond = _mm_or_si128(_mm_cmpgt_epi32(rounded, limit), _mm_cmplt_epi32(rounded, minus_limit));
  *ok = _mm_andnot_si128(beyond, _mm_castps_si128(in_range));
  return rounded;
}

void quarter_pel_keys_sse2(const float* dx, const float* dy, const uint8_t* valid, size_t count, int limit,
                           int32_t no_key, int32_t* keys) {
  const __m128 bound = _mm_set1_ps(static_cast<float>(limit) + 0.5f);
  const __m128i limit4 = _mm_set1_epi32(limit), no_key4 = _mm_set1_epi32(no_key), zero = _mm_setzero_si128();
  size_t i = 0;
  for (; i + 4 <= count; i += 4) {
    __m128i x_ok, y_ok;
    const __m128i x = round_half_away4(_mm_loadu_ps(dx + i), bound, limit4, &x_ok);
    const __m128i y = round_half_away4(_mm_loadu_ps(dy + i), bound, limit4, &y_ok);
    int32_t valid4;
    std::memcpy(&valid4, valid + i, 4);
    const __m128i bytes = _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(valid4), zero), zero);
    const __m128i ok = _mm_andnot_si128(_mm_cmpeq_epi32(bytes, zero), _mm_and_si128(x_ok, y_ok));
    const __m128i key = _mm_add_epi32(_mm_slli_epi32(y, 16), x);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(keys + i),
                     _mm_or_si128(_mm_and_si128(ok, key), _mm_andnot_si128(ok, no_key4)));
  }
  for (; i < count; ++i) keys[i] = quarter_pel_key(dx[i], dy[i], valid[i], limit, no_key);
}

unsigned run_ends_16_sse2(const int32_t* row) {
  auto load = [&](int i) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i)); };
  auto equal_mask = [](__m128i a, __m128i b) {
    return static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(a, b))));
  };
  // Keys 0-3 against 1-4 and so on; the last group against itself shifted by one key
  // (its top lane compares with 0, and bit 15 is set anyway).
  const __m128i last = load(12);
  const unsigned equal = equal_mask(load(0), load(1)) | equal_mask(load(4), load(5)) << 4 |
                         equal_mask(load(8), load(9)) << 8 | equal_mask(last, _mm_srli_si128(last, 4)) << 12;
  return (~equal & 0x7fffu) | 0x8000u;
}

}  // namespace

void init_flow_sse2(FlowKernels* kernels) {
  kernels->flow_row = flow_row_sse2;
  kernels->quarter_pel_keys = quarter_pel_keys_sse2;
  kernels->run_ends_16 = run_ends_16_sse2;
}

}  // namespace svc

SVC_TARGET_END
