// SPDX-License-Identifier: BSD-2-Clause
// Internal to the encoder's dsp layer: each kernel family fills its entries of an
// EncoderDspTable, first with the plain reference, then with each variant the CPU flags
// allow.
#pragma once

#include "codec/encoder/dsp/encoder_dsp.h"

namespace svc::codec::dsp {

void init_forward_transform_c(EncoderDspTable* table);
void init_forward_transform_4_16_c(EncoderDspTable* table);
void init_forward_transform_types_c(EncoderDspTable* table);
void init_quantize_c(EncoderDspTable* table);
void init_sad_c(EncoderDspTable* table);
void init_satd_c(EncoderDspTable* table);

#if defined(__x86_64__) || defined(__i386__)
void init_forward_transform_sse2(EncoderDspTable* table);
void init_sad_sse2(EncoderDspTable* table);
void init_forward_transform_4_16_sse41(EncoderDspTable* table);
void init_forward_transform_types_sse41(EncoderDspTable* table);
void init_quantize_sse41(EncoderDspTable* table);
void init_satd_sse41(EncoderDspTable* table);
void init_forward_transform_4_16_avx2(EncoderDspTable* table);
void init_satd_avx2(EncoderDspTable* table);
#endif

#if defined(__aarch64__)
void init_sad_neon(EncoderDspTable* table);
void init_satd_neon(EncoderDspTable* table);
#endif

}  // namespace svc::codec::dsp
