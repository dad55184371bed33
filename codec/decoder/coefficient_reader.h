// SPDX-License-Identifier: BSD-2-Clause
// Reading of quantized transform blocks (docs/codec.md section 3.4), with the contexts of
// codec/common/coefficient_contexts.h.
//
// Threading: context sets are plain mutable data owned by one coder at a time.
// Errors: the functions return false on syntax that no encoder produces (an end of block
// past the block, a level beyond kMaxLevel, an over-long escape code); they never read
// outside their inputs and always terminate.
#pragma once

#include <cstdint>

#include "codec/common/coefficient_contexts.h"
#include "codec/decoder/range_decoder.h"

namespace svc::codec {

// Decodes what encode_block_levels (codec/encoder/coefficient_writer.h) wrote: the levels
// of a block of `size`. Writes the non-zero levels in scan
// order to out[0..count) (out must hold the size's count) and sets *count. Returns false
// on invalid syntax.
bool decode_block_levels(RangeDecoder& decoder, BlockContextSet& contexts, int coded_block_context, BlockLevel* out,
                         int* count, TransformSize size = TransformSize::k8x8);

// Exp-Golomb order 0 with bypass bits, for values below 2^17 - 1 (prefix <= 16).
bool decode_exp_golomb_bypass(RangeDecoder& decoder, uint32_t* value);

}  // namespace svc::codec
