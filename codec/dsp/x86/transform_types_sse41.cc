// SSE4.1 kernels of the intra transform types other than DCT_DCT: four outputs of a row
// at once (lanes over the frequency u in the forward passes, over the sample x in the
// inverse ones), every sum in the plain kernel's order, so the float forward transforms
// round exactly as the plain code does (no fused multiply-add) and the integer inverses,
// whose 32-bit sums never overflow, agree bit for bit. The inverse skips zero
// coefficients, which add nothing; packing saturates to 16 bits as the plain clamp does.
#include <smmintrin.h>

#include "codec/dsp/dsp_init.h"
#include "codec/dsp/transform_type_basis.h"
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

// A matrix as aligned int32 rows, rows[u][x].
template <int N>
struct AlignedTypeMatrix {
  alignas(16) int32_t rows[N][N];
  explicit constexpr AlignedTypeMatrix(const TypeMatrix<N>& matrix) : rows{} {
    for (int u = 0; u < N; ++u) {
      for (int x = 0; x < N; ++x) rows[u][x] = matrix.m[u][x];
    }
  }
};

template <int N>
const AlignedTypeMatrix<N>& aligned_matrix(bool dst) {
  static const AlignedTypeMatrix<N> dct(type_matrix<N>(false)), dst_matrix(type_matrix<N>(true));
  return dst ? dst_matrix : dct;
}

template <int N>
void inverse_typed(int type, const int16_t* coefficients, int16_t* samples) {
  const bool rows_dst = (type & 1) != 0, columns_dst = (type & 2) != 0;
  const auto& rows = aligned_matrix<N>(rows_dst).rows;
  const TypeMatrix<N>& columns = type_matrix<N>(columns_dst);
  alignas(16) int32_t tmp[N * N];
  const int row_shift = type_row_shift(rows_dst);
  const __m128i row_round = _mm_set1_epi32(1 << (row_shift - 1));
  const __m128i row_bits = _mm_cvtsi32_si128(row_shift);
  for (int v = 0; v < N; ++v) {
    const int16_t* in = coefficients + N * v;
    for (int x = 0; x < N; x += 4) {
      __m128i sum = row_round;
      for (int u = 0; u < N; ++u) {
        if (in[u] == 0) continue;
        sum = _mm_add_epi32(sum, _mm_mullo_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(&rows[u][x])),
                                                 _mm_set1_epi32(in[u])));
      }
      _mm_store_si128(reinterpret_cast<__m128i*>(tmp + N * v + x), _mm_sra_epi32(sum, row_bits));
    }
  }
  const int column_shift = type_column_shift(N, columns_dst);
  const __m128i column_round = _mm_set1_epi32(1 << (column_shift - 1));
  const __m128i column_bits = _mm_cvtsi32_si128(column_shift);
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; x += 4) {
      __m128i sum = column_round;
      for (int v = 0; v < N; ++v) {
        sum =
            _mm_add_epi32(sum, _mm_mullo_epi32(_mm_set1_epi32(columns.m[v][y]),
                                               _mm_load_si128(reinterpret_cast<const __m128i*>(tmp + N * v + x))));
      }
      const __m128i out = _mm_sra_epi32(sum, column_bits);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(samples + N * y + x), _mm_packs_epi32(out, out));
    }
  }
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
