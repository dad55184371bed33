// Entropy coding of quantized 8x8 blocks with the adaptive range coder: zig-zag scan,
// coded-block flag, significance map with "last" flags, CABAC-style level magnitudes
// and a category-coded DC difference. Each block class (intra luma, intra chroma,
// non-intra luma, ...) owns a BlockContextSet; encoder and decoder must feed the same
// sequence of calls with the same context sets to stay in step. Exact syntax in
// docs/codec.md.
//
// Threading: context sets are plain mutable data owned by one coder at a time.
// Errors: decode functions return false on syntax that no encoder produces (a level
// beyond kMaxLevel, an over-long escape code); they never read outside their inputs.
#pragma once

#include <array>
#include <cstdint>

#include "codec/range_coder.h"

namespace svc::codec {

// MPEG-2 default zig-zag: kZigZag[scan index] = natural (row-major) position.
extern const std::array<uint8_t, 64> kZigZag;

inline constexpr int kCodedBlockContexts = 4;
// Pass as coded_block_context when the block is known to hold a non-zero level (the
// caller signalled it elsewhere): no coded-block flag is coded.
inline constexpr int kNoCodedBlockFlag = -1;

inline constexpr int kDcCategoryContexts = 3;
inline constexpr int kMaxDcCategory = 14;  // |difference| < 2^14

struct BlockContextSet {
  std::array<AdaptiveBit, kCodedBlockContexts> coded_block{};
  std::array<AdaptiveBit, 64> significant{};  // by scan index
  std::array<AdaptiveBit, 64> last{};         // by scan index
  std::array<AdaptiveBit, 5> greater_than_one{};
  std::array<AdaptiveBit, 5> level_remainder{};
  std::array<std::array<AdaptiveBit, kMaxDcCategory>, kDcCategoryContexts> dc_category{};
  // Category of the previous DC difference coded with this set (selects dc_category row).
  int previous_dc_category = 0;
};

// One decoded non-zero level: natural position and value.
struct BlockLevel {
  uint8_t position;
  int16_t level;
};

// Codes scan positions [first_scan, 64) of `levels` (natural order, |level| <=
// kMaxLevel): with first_scan = 1 for intra AC after a separate DC, 0 otherwise.
// coded_block_context in [0, kCodedBlockContexts) selects the coded-block flag's
// context, or kNoCodedBlockFlag (then the block must contain a non-zero level).
void encode_block_levels(RangeEncoder& encoder, BlockContextSet& contexts, const int16_t* levels, int first_scan,
                         int coded_block_context);

// Decodes what encode_block_levels wrote. Writes the non-zero levels in scan order to
// out[0..count) (out must hold 64) and sets *count. Returns false on invalid syntax.
bool decode_block_levels(RangeDecoder& decoder, BlockContextSet& contexts, int first_scan, int coded_block_context,
                         BlockLevel* out, int* count);

// DC difference (intra DC level minus its prediction), |difference| < 2^kMaxDcCategory.
void encode_dc_difference(RangeEncoder& encoder, BlockContextSet& contexts, int difference);
bool decode_dc_difference(RangeDecoder& decoder, BlockContextSet& contexts, int* difference);

// Exp-Golomb order 0 with bypass bits, for values below 2^17 - 1 (prefix <= 16).
void encode_exp_golomb_bypass(RangeEncoder& encoder, uint32_t value);
bool decode_exp_golomb_bypass(RangeDecoder& decoder, uint32_t* value);

}  // namespace svc::codec
