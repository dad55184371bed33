// Entropy coding of quantized transform blocks with the adaptive range coder, in the
// manner of HEVC/AV1: coded-block flag, end-of-block position (class + offset), then in
// reverse scan order each coefficient's significance, greater-than-1/2 flags, adaptive
// level-range bins and an Exp-Golomb-k remainder, with contexts from the already coded
// neighbours to the right and below and from the position. A category-coded DC difference
// serves blocks whose DC is predicted. Block sizes (4x4, 8x8, 16x16) are a parameter:
// scan and end-of-block contexts per size. Each block class (intra luma, intra chroma,
// non-intra luma, ...) owns a BlockContextSet; encoder and decoder must feed the same
// sequence of calls with the same context sets to stay in step. Exact syntax in
// docs/codec.md section 5.
//
// Threading: context sets are plain mutable data owned by one coder at a time.
// Errors: decode functions return false on syntax that no encoder produces (an end of
// block past the block, a level beyond kMaxLevel, an over-long escape code); they never
// read outside their inputs and always terminate.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "codec/common/range_coder.h"
#include "codec/common/transform_size.h"

namespace svc::codec {

// MPEG-2 default zig-zag: kZigZag[scan index] = natural (row-major) position.
extern const std::array<uint8_t, 64> kZigZag;

// What the context templates need of one natural position, tabulated per size so the
// per-coefficient work has no division.
struct PositionContext {
  uint16_t grid;           // index in NeighbourMagnitudes' bordered grid
  uint8_t position_class;  // 0 for the DC, 1 for row + column <= 2, 2 up to 5, 3 beyond
  uint8_t range_group;     // 0 for the DC, 1 for row and column < 2, 2 beyond
};

// A size's scan: every position comes after its left and upper neighbours (the zig-zag
// over anti-diagonals), so the reverse scan codes right and lower neighbours first.
struct ScanOrder {
  int width;                         // coefficients per row
  int height;                        // rows
  int count;                         // width * height
  const uint8_t* scan;               // scan index -> natural position (row * width + column)
  const PositionContext* positions;  // natural position -> its contexts' inputs
};
const ScanOrder& scan_order(TransformSize size);

inline constexpr int kCodedBlockContexts = 4;
// Pass as coded_block_context when the block is known to hold a non-zero level (the
// caller signalled it elsewhere): no coded-block flag is coded.
inline constexpr int kNoCodedBlockFlag = -1;

inline constexpr int kMaxEobClasses = 9;    // eob up to 256 (16x16)
inline constexpr int kPositionClasses = 4;  // by row + column: 0, 1..2, 3..5, 6..
inline constexpr int kNeighbourhoods = 5;   // significance: capped neighbour magnitude
inline constexpr int kSignificanceContexts = kPositionClasses * kNeighbourhoods;
// Greater-than-1/2: the significance context, or one per position class at the last.
inline constexpr int kBaseLevelContexts = kSignificanceContexts + kPositionClasses;
inline constexpr int kRangeContexts = 3 * 7;  // level-range bins: 3 position groups x 7
inline constexpr int kRangeLevel = 15;        // magnitudes from here take a remainder
inline constexpr int kMaxRiceParameter = 4;

inline constexpr int kDcCategoryContexts = 3;
inline constexpr int kMaxDcCategory = 14;  // |difference| < 2^14

struct BlockContextSet {
  std::array<AdaptiveBit, kCodedBlockContexts> coded_block{};
  std::array<std::array<AdaptiveBit, kMaxEobClasses>, kTransformSizes> eob_class{};
  std::array<std::array<AdaptiveBit, kMaxEobClasses>, kTransformSizes> eob_extra{};  // by class
  std::array<AdaptiveBit, kSignificanceContexts> significant{};
  std::array<AdaptiveBit, kBaseLevelContexts> greater_than_one{};
  std::array<AdaptiveBit, kBaseLevelContexts> greater_than_two{};
  std::array<AdaptiveBit, kRangeContexts> level_range{};
  std::array<std::array<AdaptiveBit, kMaxDcCategory>, kDcCategoryContexts> dc_category{};
  // Category of the previous DC difference coded with this set (selects dc_category row).
  int previous_dc_category = 0;
};

// Calls f on every context of the set, in the order of the members above (arrays in
// index order): the order of the trained initial probabilities (docs/codec.md 4).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, BlockContextSet>
void for_each_context(Set& s, F&& f) {
  for_each_bit(s.coded_block, f);
  for_each_bit(s.eob_class, f);
  for_each_bit(s.eob_extra, f);
  for_each_bit(s.significant, f);
  for_each_bit(s.greater_than_one, f);
  for_each_bit(s.greater_than_two, f);
  for_each_bit(s.level_range, f);
  for_each_bit(s.dc_category, f);
}

// One decoded non-zero level: natural position and value.
struct BlockLevel {
  uint8_t position;
  int16_t level;
};

// Magnitudes of the coefficients coded so far, in natural order with a zero border two
// wide to the right and below, so the context templates need no bounds checks.
class NeighbourMagnitudes {
 public:
  explicit NeighbourMagnitudes(const ScanOrder& order) : positions_(order.positions), stride_(order.width + 2) {
    std::fill_n(grid_.begin(), stride_ * (order.height + 2), uint16_t{0});
    std::fill_n(capped_.begin(), stride_ * (order.height + 2), uint8_t{0});
  }
  void set(int position, int magnitude) {
    const int cell = positions_[position].grid;
    grid_[cell] = static_cast<uint16_t>(magnitude);
    capped_[cell] = static_cast<uint8_t>(std::min(magnitude, 3));
  }
  // Contexts of natural position `position` (docs/codec.md 5.2).
  int significance_context(int position) const {
    const uint8_t* a = capped_.data() + positions_[position].grid;
    const int s = stride_;
    const int magnitude = a[1] + a[s] + a[s + 1] + a[2] + a[2 * s];
    return positions_[position].position_class * kNeighbourhoods +
           std::min((magnitude + 1) >> 1, kNeighbourhoods - 1);
  }
  int range_context(int position) const;
  int rice_parameter(int position) const;

 private:
  const PositionContext* positions_;
  int stride_;
  std::array<uint16_t, (kMaxTransformWidth + 2) * (kMaxTransformWidth + 2)> grid_;
  // min(magnitude, 3), all the significance contexts read: no clamp per neighbour.
  std::array<uint8_t, (kMaxTransformWidth + 2) * (kMaxTransformWidth + 2)> capped_;
};

// The greater-than-1/2 context of the last significant coefficient (its neighbours to the
// right and below are all zero, and its significance is implied): one per position class
// (0 for the DC, 1 for row + column <= 2, 2 up to 5, 3 beyond).
inline int last_level_context(const ScanOrder& order, int position) {
  return kSignificanceContexts + order.positions[position].position_class;
}

// Codes scan positions [first_scan, count) of `levels` (natural order, |level| <=
// kMaxLevel): with first_scan = 1 for intra AC after a separate DC, 0 otherwise.
// coded_block_context in [0, kCodedBlockContexts) selects the coded-block flag's
// context, or kNoCodedBlockFlag (then the block must contain a non-zero level).
void encode_block_levels(RangeEncoder& encoder, BlockContextSet& contexts, const int16_t* levels, int first_scan,
                         int coded_block_context, TransformSize size = TransformSize::k8x8);

// Decodes what encode_block_levels wrote. Writes the non-zero levels in scan order to
// out[0..count) (out must hold the size's count) and sets *count. Returns false on
// invalid syntax.
bool decode_block_levels(RangeDecoder& decoder, BlockContextSet& contexts, int first_scan, int coded_block_context,
                         BlockLevel* out, int* count, TransformSize size = TransformSize::k8x8);

// Encoder only: the bits encode_block_levels would write, from the contexts' current
// probabilities (unchanged).
float block_levels_bits(const BlockContextSet& contexts, const int16_t* levels, int first_scan,
                        int coded_block_context, TransformSize size = TransformSize::k8x8);
// block_levels_bits of a block without levels: its coded-block flag (0), if coded.
float uncoded_block_bits(const BlockContextSet& contexts, int coded_block_context);

// Encoder only, for rate-distortion quantization: bits of the end-of-block position
// `last_scan` (first_scan .. the size's count - 1), the sum write_end_of_block forms,
// from per-class partial sums taken once for the many positions a search prices.
class EndOfBlockPricer {
 public:
  EndOfBlockPricer(const BlockContextSet& contexts, int first_scan, TransformSize size);
  float bits(int last_scan) const;

 private:
  const AdaptiveBit* extra_;  // eob_extra of the size
  int first_scan_;
  // Per end-of-block class: its unary bits and terminating bit (if any), summed in order.
  std::array<float, kMaxEobClasses + 1> class_bits_{};
};

// Encoder only: bits of one non-zero magnitude with its sign at natural `position`, given
// the magnitudes coded before it and its `base_context` (significance context, or
// last_level_context at the end of block), without the significance flag.
float magnitude_bits(const BlockContextSet& contexts, const NeighbourMagnitudes& neighbours, int position,
                     int base_context, int magnitude);

// DC difference (intra DC level minus its prediction), |difference| < 2^kMaxDcCategory.
void encode_dc_difference(RangeEncoder& encoder, BlockContextSet& contexts, int difference);
bool decode_dc_difference(RangeDecoder& decoder, BlockContextSet& contexts, int* difference);

// Exp-Golomb order 0 with bypass bits, for values below 2^17 - 1 (prefix <= 16).
void encode_exp_golomb_bypass(RangeEncoder& encoder, uint32_t value);
bool decode_exp_golomb_bypass(RangeDecoder& decoder, uint32_t* value);

}  // namespace svc::codec
