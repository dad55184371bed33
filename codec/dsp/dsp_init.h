// Internal to the dsp layer: each kernel family fills its entries of a DspTable, first
// with the plain reference, then with each variant the CPU flags allow.
#pragma once

#include "codec/dsp/dsp.h"

namespace svc::codec::dsp {

void init_transform_c(DspTable* table);
void init_quant_c(DspTable* table);
void init_color_c(DspTable* table);
void init_mc_c(DspTable* table);
void init_warp_c(DspTable* table);
void init_deblock_c(DspTable* table);
void init_cdef_c(DspTable* table);

// Plain kernels that x86 variants fall back to for the sizes they do not specialise.
void put_half_pel_c(const uint8_t* window, ptrdiff_t window_stride, int width, int height, int fx, int fy,
                    uint8_t* out, ptrdiff_t out_stride);
void rgb_to_luma_row_c(const uint8_t* rgb, int width, uint8_t* y);
void rgb_to_chroma_row_c(const uint8_t* row0, const uint8_t* row1, int width, uint8_t* cb, uint8_t* cr);
void ycbcr_to_rgb_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgb);

#if defined(__x86_64__) || defined(__i386__)
void init_mc_sse2(DspTable* table);
void init_transform_sse2(DspTable* table);
void init_warp_sse2(DspTable* table);
void init_color_sse2(DspTable* table);
void init_color_sse41(DspTable* table);
void init_deblock_sse41(DspTable* table);
void init_cdef_sse41(DspTable* table);
void init_mc_avx2(DspTable* table);
#endif

}  // namespace svc::codec::dsp
