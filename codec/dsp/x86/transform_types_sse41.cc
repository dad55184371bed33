// SSE4.1 kernels of the intra transform types other than DCT_DCT: four outputs of a row
// at once (lanes over the frequency u in the forward passes, over the sample x in the
// inverse ones), every sum in the plain kernel's order, so the float forward transforms
// round exactly as the plain code does (no fused multiply-add). The integer inverses are
// matrix_inverse_sse41.h's.
#include <smmintrin.h>

#include "codec/dsp/dsp_init.h"
#include "codec/dsp/transform_type_basis.h"
#include "codec/dsp/x86/matrix_inverse_sse41.h"
#include "codec/dsp/x86/transposed_basis.h"

#pragma GCC target("sse4.1")

namespace svc::codec::dsp {
namespace {

template <int N>
const TransposedBasis<N>& transposed_basis(bool dst) {
  static const TransposedBasis<N> dct(type_float_basis<N>(false)), dst_basis(type_float_basis<N>(true));
  return dst ? dst_basis : dct;
}

template <int N>
void forward_typed(int type, const float* samples, float* coefficients) {
  const TransposedBasis<N>& rows = transposed_basis<N>((type & 1) != 0);
  const TypeFloatBasis<N>& columns = type_float_basis<N>((type & 2) != 0);
  alignas(16) float tmp[N * N];
  for (int y = 0; y < N; ++y) {
    for (int u = 0; u < N; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int x = 0; x < N; ++x) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_load_ps(&rows.bt[x][u]), _mm_set1_ps(samples[N * y + x])));
      }
      _mm_store_ps(tmp + N * y + u, sum);
    }
  }
  const __m128 factor = _mm_set1_ps(type_forward_scale(N));
  for (int v = 0; v < N; ++v) {
    for (int u = 0; u < N; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int y = 0; y < N; ++y) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(columns.b[v][y]), _mm_load_ps(tmp + N * y + u)));
      }
      _mm_storeu_ps(coefficients + N * v + u, _mm_mul_ps(sum, factor));
    }
  }
}

// A direction's matrix (DST-VII when `dst`, else the DCT) in the inverse's layouts.
template <int N>
const InverseMatrixPairs<N>& matrix_pairs(bool dst) {
  static const InverseMatrixPairs<N> dct(type_matrix<N>(false).m), dst_pairs(type_matrix<N>(true).m);
  return dst ? dst_pairs : dct;
}

template <int N>
void inverse_typed(int type, const int16_t* coefficients, int16_t* samples) {
  const bool rows_dst = (type & 1) != 0, columns_dst = (type & 2) != 0;
  inverse_matrix_transform<N>(matrix_pairs<N>(rows_dst), type_row_shift(rows_dst), matrix_pairs<N>(columns_dst),
                              type_column_shift(N, columns_dst), coefficients, samples);
}

}  // namespace

void init_transform_types_sse41(DspTable* table) {
  table->forward_typed_4x4 = forward_typed<4>;
  table->forward_typed_8x8 = forward_typed<8>;
  table->forward_typed_16x16 = forward_typed<16>;
  table->inverse_typed_4x4 = inverse_typed<4>;
  table->inverse_typed_8x8 = inverse_typed<8>;
  table->inverse_typed_16x16 = inverse_typed<16>;
}

}  // namespace svc::codec::dsp
