// SPDX-License-Identifier: BSD-2-Clause
// The pixel kernels that encoder and decoder share behind one table of function pointers,
// filled once by CPU features (the pattern of dav1d's mc.h and libwebp's dsp/): every
// kernel has a plain C++ reference, always compiled, and optional x86 or AArch64 NEON
// variants that must match it bit for bit. The codec calls kernels only through
// get_dsp(); tests and the kernel checker build tables for chosen feature sets with
// make_dsp_table(). The encoder's own kernels (forward transforms, quantization, SAD,
// SATD) have a table of their own built by the same rules
// (codec/encoder/dsp/encoder_dsp.h). docs/kernels.md describes how to add a kernel or a
// variant.
#pragma once

#include <cstddef>
#include <cstdint>

#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"

namespace svc::codec::dsp {

// CPU feature bits a variant may need. A table built for a mask uses, per kernel, the
// most capable variant whose features are all in the mask.
enum CpuFlag : unsigned {
  kCpuSse2 = 1u << 0,
  kCpuSse41 = 1u << 1,
  kCpuAvx2 = 1u << 2,
  kCpuNeon = 1u << 3,  // AArch64 Advanced SIMD
};

// Features this machine has: the x86 ones by CPUID, kCpuNeon on AArch64 (where every
// processor has it), 0 elsewhere.
unsigned detected_cpu_flags();
// detected_cpu_flags() restricted by the SVC_CPU_MASK environment variable when it is set
// (a number, e.g. 0 for the plain references only, 0x1 for SSE2); read once.
unsigned active_cpu_flags();

// Samples of an 8x8 block's intra prediction edge: 16 left (bottom to top), the corner,
// 16 above. An N x N block's edge has 4N + 1 samples, the corner at 2N; the largest
// (16x16) has kMaxIntraEdgeSamples.
inline constexpr int kIntraEdgeSamples = 33;
inline constexpr int kMaxIntraEdgeSamples = 65;

// The CDEF filter of one block (docs/codec.md, section 5.8.2).
struct CdefTaps {
  int primary;    // primary strength after the contrast adjustment, 0..15
  int secondary;  // secondary strength: 0, 1, 2 or 4
  int direction;  // 0..7
  int damping;    // 2..6
};
// A CDEF input sample outside the plane: it takes no part in the filter.
inline constexpr uint16_t kCdefUnavailable = 30000;

// The weights of a bilinear sample of a 2 x 2 block as two 1-D pairs, each summing to
// 16: columns (x0, x1) and rows (y0, y1), so sample (r, c) weighs y_r x_c.
struct BilinearWeights {
  uint8_t x0, x1, y0, y1;
  bool operator==(const BilinearWeights&) const = default;
};

struct DspTable {
  // The bit-exact integer inverse transforms (docs/codec.md 5.5), coefficients in
  // [-2048, 2047], blocks row-major: the 8x8 DCT; the 4x4 and 16x16 DCTs with HEVC's
  // matrices; the intra transform types with a DST-VII in at least one direction (7.2),
  // `type` 1..3 (bit 0: rows use the DST, bit 1: columns; the other direction takes
  // HEVC's integer DCT of the size, at 8x8 too); and the rectangular blocks (7.3; W x H,
  // W samples a row), types 0..3, 0 being DCT_DCT. The encoder's float forward
  // transforms are in its own table (codec/encoder/dsp/encoder_dsp.h).
  // Indexed by TransformSize and TransformType: [k8x8][kDctDct] is the 8x8 DCT,
  // [k4x4][kDctDct] and [k16x16][kDctDct] the HEVC DCTs, the other entries of the squares
  // the typed kernels, and every entry of a rectangular size its typed kernel.
  void (*inverse_transform[kTransformSizes][kTransformTypes])(const int16_t* coefficients, int16_t* samples);

  // Reconstruction of a residual block, indexed by TransformSize and TransformType (as
  // dav1d's itxfm_add): dst = clip(prediction + inverse transform of `coefficients`, 0,
  // 255), the inverse being inverse_transform[size][type]. prediction and dst are W x H samples with their own
  // strides; dst may be prediction.
  void (*inverse_transform_add[kTransformSizes][kTransformTypes])(const int16_t* coefficients,
                                                                  const uint8_t* prediction,
                                                                  ptrdiff_t prediction_stride, uint8_t* dst,
                                                                  ptrdiff_t dst_stride);

  // coefficient = sign(level) ((min(|level|, 4096) scale[i] + 128) >> 8) saturated to
  // [-2048, 2047]; scale[i] in 128..2^18 (codec/common/quant.h).
  void (*dequantize_8x8)(const int16_t* levels, const int32_t* scale, int16_t* coefficients);

  // Color conversion (codec/encoder/rgb_to_ycbcr.h, codec/common/color.h): one row of
  // luma from packed RGB; one row of 4:2:0 chroma from two RGB rows (row1 may equal row0;
  // odd widths replicate the last pixel); one RGB row from luma and a half-width chroma
  // row.
  void (*rgb_to_luma_row)(const uint8_t* rgb, int width, uint8_t* y);
  void (*rgb_to_chroma_row)(const uint8_t* row0, const uint8_t* row1, int width, uint8_t* cb, uint8_t* cr);
  void (*ycbcr_to_rgb_row)(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgb);
  // The same row as 4-byte pixels with alpha 255, in memory order R, G, B, A (rgba) or
  // B, G, R, A (bgra): the formats GPUs upload. Write exactly 4 * width bytes, at any
  // alignment.
  void (*ycbcr_to_rgba_row)(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgba);
  void (*ycbcr_to_bgra_row)(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* bgra);

  // Separable 8-tap interpolation (docs/codec.md, section 5.6): `window` points at the
  // top-left tap, 3 samples left of and above the block's integer position, and holds
  // (width + 7) x (height + 7) samples; h_taps and v_taps hold 8 coefficients each
  // (summing to 64). out = ((sum_j v[j] sum_i h[i] window[y + j][x + i]) >> 6) - 8192,
  // the intermediate sample of 14 bits less the offset that makes it fit int16. Widths
  // 4 to 64 in steps of 4, heights 1 to 64. Rows may be read up to 8 samples past the
  // taps' reach (width + 7): by 1 sample when the width is a multiple of 8.
  void (*interpolate_8tap)(const uint8_t* window, ptrdiff_t window_stride, int width, int height,
                           const int8_t* h_taps, const int8_t* v_taps, int16_t* out, ptrdiff_t out_stride);
  // Single prediction from intermediates: clip((in + 8192 + 32) >> 6, 0, 255).
  void (*put_intermediate)(const int16_t* in, int count, uint8_t* out);
  // Bidirectional prediction: clip((a + b + 2 * 8192 + 64) >> 7, 0, 255).
  void (*average_intermediate)(const int16_t* a, const int16_t* b, int count, uint8_t* out);
  // Intra prediction of a block, indexed by its TransformSize (W x H samples out, W a
  // row), in mode 0..34 (planar, DC, angles; docs/codec.md 5.2) from its edge of
  // 2 (W + H) + 1 samples: edge[W + H - 1 - i] is the left neighbour of row i
  // (i = 0..W+H-1, rows H.. below the block), edge[W + H] the top-left corner,
  // edge[W + H + 1 + i] the sample above column i.
  void (*intra_predict[kTransformSizes])(const uint8_t* edge, int mode, uint8_t* out);
  // Chroma from luma (docs/codec.md 3.3): the 8x8 chroma block's luma, `luma` pointing at
  // its 16x16 co-located samples, as 2x2 sums minus their rounded mean over the block
  // (64 values in -1020..1020, row-major); and the prediction
  // clip(dc + ((alpha * ac + 16) >> 5), 0, 255) for dc in 0..255, alpha in -16..16.
  void (*cfl_luma_ac_8x8)(const uint8_t* luma, ptrdiff_t stride, int16_t* ac);
  void (*cfl_predict_8x8)(const int16_t* ac, int dc, int alpha, uint8_t* out);

  // Deblocking of `segments` consecutive 4-sample segments of one edge (docs/codec.md,
  // section 5.8): `pixels` is q0 of the first line, p_i lies at pixels - (i + 1) across,
  // q_i at pixels + i across, line l at pixels + l along; one of across and along is 1.
  // Segment s (lines 4s..4s+3) is filtered with tc[s] (0..24; 0 leaves it alone), each
  // segment making its own decisions. Luma reads p3..q3 and writes at most p2..q2;
  // chroma reads p1..q1 and writes p0, q0. beta 0..64.
  void (*deblock_luma)(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, int beta,
                       const uint8_t* tc);
  void (*deblock_chroma)(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, const uint8_t* tc);

  // CDEF (docs/codec.md, section 5.8.2): the direction 0..7 of an 8x8 block and, in
  // *variance, the contrast of its best line fit against the orthogonal one.
  int (*cdef_direction_8x8)(const uint8_t* pixels, ptrdiff_t stride, int32_t* variance);
  // Filters a size x size block (8 or 4) of 16-bit samples `in` (the block's first
  // sample, with 2 readable samples on every side, kCdefUnavailable outside the plane)
  // into `out`.
  void (*cdef_filter_block)(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride, int size,
                            const CdefTaps& taps);

  // Geometry padding of cube faces (docs/codec.md 5.7): `count` bilinear samples of a
  // plane `stride` samples wide, out[k] = (w.y0 (w.x0 p[0] + w.x1 p[1]) + w.y1 (w.x0
  // p[stride] + w.x1 p[stride + 1]) + 128) >> 8 with p = plane + index[k], w =
  // weights[k]. Each 2 x 2 block lies inside the plane (its left column below
  // stride - 1), and index[k] + stride + 1 < 2^31. Reads stay within each block's rows.
  void (*pad_sample_run)(const uint8_t* plane, ptrdiff_t stride, const uint32_t* index,
                         const BilinearWeights* weights, int count, uint8_t* out);
};

// The table for this machine (active_cpu_flags()), built once on first use; thread-safe.
// Inline, as every block calls it: after the first call it costs one initialised test.
const DspTable& build_process_dsp_table();
inline const DspTable& get_dsp() {
  static const DspTable& table = build_process_dsp_table();
  return table;
}
// A table using only variants whose features are in `cpu_flags` (0: plain references).
DspTable make_dsp_table(unsigned cpu_flags);

}  // namespace svc::codec::dsp
