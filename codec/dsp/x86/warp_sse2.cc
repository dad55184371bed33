// SSE2 warped-prediction kernel. Gathers stay scalar; the weighting runs eight samples at
// a time in 16 bits as t = 16 a + fx (b - a), u = 16 c + fx (d - c),
// p = (16 t + fy (u - t) + 128) >> 8, which equals the plain kernel's bilinear weighting
// exactly (the result and every partial sum fit 16 bits unsigned, so wrapping
// intermediate differences cancel).
#include <emmintrin.h>

#include "codec/dsp/dsp_init.h"

#pragma GCC target("sse2")

namespace svc::codec::dsp {
namespace {

constexpr int kMaxCount = 16;

void warp_row_sse2(const uint8_t* plane, ptrdiff_t stride, const WarpRow& r, uint8_t* out) {
  alignas(16) uint16_t a[kMaxCount], b[kMaxCount], c[kMaxCount], d[kMaxCount], fx[kMaxCount], fy[kMaxCount];
  const int round = 1 << (r.shift - 1);
  const int count = r.count < kMaxCount ? r.count : kMaxCount;
  int sx = r.sx, sy = r.sy;
  for (int u = 0; u < count; ++u, sx += r.step_x, sy += r.step_y) {
    const int X = r.x16 + 16 * u + ((sx + round) >> r.shift), Y = r.y16 + ((sy + round) >> r.shift);
    const uint8_t* p = plane + (Y >> 4) * stride + (X >> 4);
    a[u] = p[0];
    b[u] = p[1];
    c[u] = p[stride];
    d[u] = p[stride + 1];
    fx[u] = static_cast<uint16_t>(X & 15);
    fy[u] = static_cast<uint16_t>(Y & 15);
  }
  const __m128i rounding = _mm_set1_epi16(128);
  for (int u = 0; u < count; u += 8) {
    auto load = [u](const uint16_t* v) { return _mm_load_si128(reinterpret_cast<const __m128i*>(v + u)); };
    const __m128i va = load(a), vc = load(c), vfx = load(fx), vfy = load(fy);
    const __m128i top = _mm_add_epi16(_mm_slli_epi16(va, 4), _mm_mullo_epi16(vfx, _mm_sub_epi16(load(b), va)));
    const __m128i bottom = _mm_add_epi16(_mm_slli_epi16(vc, 4), _mm_mullo_epi16(vfx, _mm_sub_epi16(load(d), vc)));
    const __m128i sum = _mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(top, 4), rounding),
                                      _mm_mullo_epi16(vfy, _mm_sub_epi16(bottom, top)));
    const __m128i value = _mm_srli_epi16(sum, 8);
    const __m128i bytes = _mm_packus_epi16(value, value);
    if (count - u >= 8) {
      _mm_storel_epi64(reinterpret_cast<__m128i*>(out + u), bytes);
    } else {
      alignas(16) uint8_t tail[16];
      _mm_store_si128(reinterpret_cast<__m128i*>(tail), bytes);
      for (int i = 0; i < count - u; ++i) out[u + i] = tail[i];
    }
  }
}

}  // namespace

void init_warp_sse2(DspTable* table) { table->warp_row = warp_row_sse2; }

}  // namespace svc::codec::dsp
