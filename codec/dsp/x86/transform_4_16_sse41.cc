// SSE4.1 4x4 and 16x16 transforms. Both compute four outputs of a row at once (lanes
// over the frequency u in the forward passes, over the sample x in the inverse ones)
// with every sum in the plain kernel's order, so the float forward transforms round
// exactly as the plain code does (no fused multiply-add), and the integer inverses,
// whose 32-bit sums never overflow, agree bit for bit. The inverse skips zero
// coefficients, which add nothing; packing saturates to 16 bits as the plain kernel's
// clamp does.
#include <smmintrin.h>

#include "codec/dsp/dct_4_16_basis.h"
#include "codec/dsp/dsp_init.h"
#include "codec/dsp/x86/transposed_basis.h"

#pragma GCC target("sse4.1")

namespace svc::codec::dsp {
namespace {

template <int N>
void forward_dct(const ForwardDctFloatBasis<N>& basis, const TransposedBasis<N>& transposed, float scale,
                 const float* samples, float* coefficients) {
  alignas(16) float tmp[N * N];
  for (int y = 0; y < N; ++y) {
    for (int u = 0; u < N; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int x = 0; x < N; ++x) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_load_ps(&transposed.bt[x][u]), _mm_set1_ps(samples[N * y + x])));
      }
      _mm_store_ps(tmp + N * y + u, sum);
    }
  }
  const __m128 factor = _mm_set1_ps(scale);
  for (int v = 0; v < N; ++v) {
    for (int u = 0; u < N; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int y = 0; y < N; ++y) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(basis.b[v][y]), _mm_load_ps(tmp + N * y + u)));
      }
      _mm_storeu_ps(coefficients + N * v + u, _mm_mul_ps(sum, factor));
    }
  }
}

void forward_dct_4x4_sse41(const float* samples, float* coefficients) {
  static const TransposedBasis<4> transposed(kForwardDct4Basis);
  forward_dct(kForwardDct4Basis, transposed, 1.0f, samples, coefficients);
}

void forward_dct_16x16_sse41(const float* samples, float* coefficients) {
  static const TransposedBasis<16> transposed(kForwardDct16Basis);
  forward_dct(kForwardDct16Basis, transposed, 0.5f, samples, coefficients);
}

// The matrix as aligned int32 rows, rows[u][x].
template <int N>
struct MatrixRows {
  alignas(16) int32_t rows[N][N];
  explicit MatrixRows(const HevcDctMatrix<N>& matrix) {
    for (int u = 0; u < N; ++u) {
      for (int x = 0; x < N; ++x) rows[u][x] = matrix.m[u][x];
    }
  }
};

template <int N>
void inverse_dct(const HevcDctMatrix<N>& matrix, const MatrixRows<N>& matrix_rows, int row_shift, int column_shift,
                 const int16_t* coefficients, int16_t* samples) {
  alignas(16) int32_t tmp[N * N];
  const auto& rows = matrix_rows.rows;
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
  const __m128i column_round = _mm_set1_epi32(1 << (column_shift - 1));
  const __m128i column_bits = _mm_cvtsi32_si128(column_shift);
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; x += 4) {
      __m128i sum = column_round;
      for (int v = 0; v < N; ++v) {
        sum =
            _mm_add_epi32(sum, _mm_mullo_epi32(_mm_set1_epi32(matrix.m[v][y]),
                                               _mm_load_si128(reinterpret_cast<const __m128i*>(tmp + N * v + x))));
      }
      const __m128i out = _mm_sra_epi32(sum, column_bits);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(samples + N * y + x), _mm_packs_epi32(out, out));
    }
  }
}

void inverse_dct_4x4_sse41(const int16_t* coefficients, int16_t* samples) {
  static const MatrixRows<4> rows(kDct4Matrix);
  inverse_dct(kDct4Matrix, rows, kIdct4RowShift, kIdct4ColumnShift, coefficients, samples);
}

void inverse_dct_16x16_sse41(const int16_t* coefficients, int16_t* samples) {
  static const MatrixRows<16> rows(kDct16Matrix);
  inverse_dct(kDct16Matrix, rows, kIdct16RowShift, kIdct16ColumnShift, coefficients, samples);
}

}  // namespace

void init_transform_4_16_sse41(DspTable* table) {
  table->forward_dct_4x4 = forward_dct_4x4_sse41;
  table->forward_dct_16x16 = forward_dct_16x16_sse41;
  table->inverse_dct_4x4 = inverse_dct_4x4_sse41;
  table->inverse_dct_16x16 = inverse_dct_16x16_sse41;
}

}  // namespace svc::codec::dsp
