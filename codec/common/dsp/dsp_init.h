// SPDX-License-Identifier: BSD-2-Clause
// Internal to the dsp layer: each kernel family fills its entries of a DspTable, first
// with the plain reference, then with each variant the CPU flags allow.
#pragma once

#include "codec/common/dsp/dsp.h"

namespace svc::codec::dsp {

void init_transform_c(DspTable* table);
void init_transform_4_16_c(DspTable* table);
void init_transform_types_c(DspTable* table);
void init_quant_c(DspTable* table);
void init_color_c(DspTable* table);
void init_mc_c(DspTable* table);
void init_intra_c(DspTable* table);
void init_deblock_c(DspTable* table);
void init_cdef_c(DspTable* table);
void init_cfl_c(DspTable* table);
void init_pad_c(DspTable* table);

// Interpolation: the largest block side and the offset of stored intermediates.
inline constexpr int kMaxInterpolationBlock = 64;
inline constexpr int kIntermediateOffset = 8192;

// Plain kernels that the variants fall back to for the sizes they do not specialise.
void interpolate_8tap_c(const uint8_t* window, ptrdiff_t window_stride, int width, int height, const int8_t* h_taps,
                        const int8_t* v_taps, int16_t* out, ptrdiff_t out_stride);
void put_intermediate_c(const int16_t* in, int count, uint8_t* out);
void average_intermediate_c(const int16_t* a, const int16_t* b, int count, uint8_t* out);
void rgb_to_luma_row_c(const uint8_t* rgb, int width, uint8_t* y);
void rgb_to_chroma_row_c(const uint8_t* row0, const uint8_t* row1, int width, uint8_t* cb, uint8_t* cr);
void intra_predict_4x4_c(const uint8_t* edge, int mode, uint8_t* out);
void intra_predict_8x8_c(const uint8_t* edge, int mode, uint8_t* out);
void intra_predict_16x16_c(const uint8_t* edge, int mode, uint8_t* out);
// The plain kernels of the rectangular W x H blocks (16x8, 8x16, 16x4, 4x16, 8x4, 4x8;
// also the SIMD variants' DC, and planar on NEON).
template <int W, int H>
void intra_predict_rectangular_c(const uint8_t* edge, int mode, uint8_t* out);
// The reference row of an angular mode (2..34), smoothed where the mode asks:
// main[kIntraAngularReferenceOffset + k], k = -8..17, is sample k of the projected edge.
inline constexpr int kIntraAngularReferenceOffset = 8;
struct IntraAngularReference {
  int angle;  // 1/32 sample per row
  uint8_t main[kIntraAngularReferenceOffset + 18];
};
void prepare_intra_angular_reference(const uint8_t* edge, int mode, IntraAngularReference* out);
// The same for the W x H block of `size`, whose edge holds 2 (W + H) + 1 samples, the
// corner at W + H. A square N x N block: main[N + k], k = -N..2N+1, is sample k of the
// projected edge (main holds 3N + 2 samples). A rectangular one (16x8, 8x16, 16x4, 4x16,
// 8x4, 4x8): main[W + H + k], k = -(W + H)..W + H + 1 (main holds 3 (W + H) + 2
// samples), of the block predicted along its columns (W x H for vertical modes, H x W,
// to be transposed, for horizontal ones). Returns the angle.
int prepare_intra_angular_reference(const uint8_t* edge, int mode, TransformSize size, uint8_t* main);
// The [1 2 1] smoothing of the edge of a block of `size` (the ends kept) that planar
// prediction and the diagonal modes read.
void smooth_intra_edge(const uint8_t* edge, TransformSize size, uint8_t* out);
// The boundary filter of DC (mode 1), pure horizontal (10) and pure vertical (26) over
// the unfiltered prediction `out` of a block of `size`, from its unsmoothed edge; other
// modes are left alone (docs/codec.md 5.2). Every variant of the angular modes calls it.
void filter_intra_boundary(const uint8_t* edge, int mode, TransformSize size, uint8_t* out);
void ycbcr_to_rgb_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgb);
void ycbcr_to_rgba_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgba);
void ycbcr_to_bgra_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* bgra);

#if defined(__x86_64__) || defined(__i386__)
void init_mc_sse2(DspTable* table);
void init_transform_sse2(DspTable* table);
void init_mc_sse41(DspTable* table);
void init_color_sse2(DspTable* table);
void init_color_sse41(DspTable* table);
void init_intra_sse41(DspTable* table);
void init_transform_4_16_sse41(DspTable* table);
void init_transform_types_sse41(DspTable* table);
void init_deblock_sse41(DspTable* table);
void init_cdef_sse41(DspTable* table);
void init_cfl_sse41(DspTable* table);
void init_quant_sse41(DspTable* table);
void init_mc_avx2(DspTable* table);
void init_cdef_avx2(DspTable* table);
void init_color_avx2(DspTable* table);
void init_pad_avx2(DspTable* table);
#endif

#if defined(__aarch64__)
void init_transform_neon(DspTable* table);
void init_transform_4_16_neon(DspTable* table);
void init_transform_types_neon(DspTable* table);
void init_quant_neon(DspTable* table);
void init_color_neon(DspTable* table);
void init_mc_neon(DspTable* table);
void init_intra_neon(DspTable* table);
void init_deblock_neon(DspTable* table);
void init_cdef_neon(DspTable* table);
void init_cfl_neon(DspTable* table);
#endif

}  // namespace svc::codec::dsp
