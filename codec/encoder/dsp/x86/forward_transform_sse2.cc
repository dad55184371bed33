// SPDX-License-Identifier: BSD-2-Clause
// SSE2 8x8 float forward DCT: the plain kernel's float butterflies on four blocks rows
// (or columns) at once, with every product and sum in the same order and no fused
// multiply-add, so each lane rounds exactly as the plain code does.
#include <emmintrin.h>
#include <xmmintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/fdct_basis.h"

SVC_TARGET_BEGIN("sse2")

namespace svc::codec::dsp {
namespace {

// An 8x8 float block as rows of two vectors (columns 0-3, 4-7).
using FloatBlock = __m128[8][2];

void transpose_8x8_ps(const FloatBlock in, FloatBlock out) {
  for (int rh = 0; rh < 2; ++rh) {
    for (int ch = 0; ch < 2; ++ch) {
      __m128 a = in[4 * rh][ch], b = in[4 * rh + 1][ch], c = in[4 * rh + 2][ch], d = in[4 * rh + 3][ch];
      _MM_TRANSPOSE4_PS(a, b, c, d);
      out[4 * ch][rh] = a;
      out[4 * ch + 1][rh] = b;
      out[4 * ch + 2][rh] = c;
      out[4 * ch + 3][rh] = d;
    }
  }
}

// The basis with each weight in all four lanes.
struct BroadcastBasis {
  __m128 even[4][4], odd[4][4];  // [k][x]
  BroadcastBasis() {
    for (int k = 0; k < 4; ++k) {
      for (int x = 0; x < 4; ++x) {
        even[k][x] = _mm_set1_ps(kForwardDctBasis.even[k][x]);
        odd[k][x] = _mm_set1_ps(kForwardDctBasis.odd[k][x]);
      }
    }
  }
};

// ((w0 v0 + w1 v1) + w2 v2) + w3 v3, the plain kernel's order.
inline __m128 dot4(const __m128 w[4], const __m128 v[4]) {
  __m128 sum = _mm_add_ps(_mm_mul_ps(w[0], v[0]), _mm_mul_ps(w[1], v[1]));
  sum = _mm_add_ps(sum, _mm_mul_ps(w[2], v[2]));
  return _mm_add_ps(sum, _mm_mul_ps(w[3], v[3]));
}

// One 1-D forward pass of eight transforms: in[x] holds sample x of each (one per lane),
// out[u] frequency u.
void forward_pass(const BroadcastBasis& b, const FloatBlock in, FloatBlock out) {
  for (int half = 0; half < 2; ++half) {
    __m128 sum[4], diff[4];
    for (int x = 0; x < 4; ++x) {
      sum[x] = _mm_add_ps(in[x][half], in[7 - x][half]);
      diff[x] = _mm_sub_ps(in[x][half], in[7 - x][half]);
    }
    for (int k = 0; k < 4; ++k) {
      out[2 * k][half] = dot4(b.even[k], sum);
      out[2 * k + 1][half] = dot4(b.odd[k], diff);
    }
  }
}

void forward_dct_8x8_sse2(const float* samples, float* coefficients) {
  static const BroadcastBasis basis;
  FloatBlock block, columns;
  for (int y = 0; y < 8; ++y) {
    block[y][0] = _mm_loadu_ps(samples + 8 * y);
    block[y][1] = _mm_loadu_ps(samples + 8 * y + 4);
  }
  transpose_8x8_ps(block, columns);     // columns[x]: sample x of every row
  forward_pass(basis, columns, block);  // block[u]: frequency u of every row
  transpose_8x8_ps(block, columns);     // columns[y]: row y of the row pass
  forward_pass(basis, columns, block);  // block[v]: frequency v of every column
  for (int v = 0; v < 8; ++v) {
    _mm_storeu_ps(coefficients + 8 * v, block[v][0]);
    _mm_storeu_ps(coefficients + 8 * v + 4, block[v][1]);
  }
}

}  // namespace

void init_forward_transform_sse2(EncoderDspTable* table) { table->forward_dct_8x8 = forward_dct_8x8_sse2; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
