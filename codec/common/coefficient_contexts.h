// SPDX-License-Identifier: BSD-2-Clause
// The contexts and scans of the coefficient syntax (docs/codec.md section 3.4), shared by
// its reader (codec/decoder/coefficient_reader.h) and writer
// (codec/encoder/coefficient_writer.h): coded-block flag, end-of-block position (class +
// offset), then in reverse scan order each coefficient's significance, greater-than-1/2
// flags, adaptive level-range bins and an Exp-Golomb-k remainder, with contexts from the
// already coded neighbours to the right and below and from the position, in the manner
// of HEVC/AV1. Block sizes are a parameter: scan and end-of-block contexts per size. Each
// block class (intra luma, intra chroma, non-intra luma, ...) owns a BlockContextSet;
// reader and writer must feed the same sequence of calls with the same context sets to
// stay in step.
//
// Threading: context sets are plain mutable data owned by one coder at a time.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

#include "codec/common/adaptive_bit.h"
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
  uint8_t position;        // the natural position itself
};

// A size's scan: every position comes after its left and upper neighbours (the zig-zag
// over anti-diagonals), so the reverse scan codes right and lower neighbours first.
struct ScanOrder {
  int width;            // coefficients per row
  int height;           // rows
  int count;            // width * height
  const uint8_t* scan;  // scan index -> natural position (row * width + column)
  // scan index -> its position's contexts' inputs (the position too), so that the
  // coefficient loops start a coefficient from one load.
  const PositionContext* scanned;
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

struct BlockContextSet {
  std::array<AdaptiveBit, kCodedBlockContexts> coded_block{};
  std::array<std::array<AdaptiveBit, kMaxEobClasses>, kTransformSizes> eob_class{};
  std::array<std::array<AdaptiveBit, kMaxEobClasses>, kTransformSizes> eob_extra{};  // by class
  std::array<AdaptiveBit, kSignificanceContexts> significant{};
  std::array<AdaptiveBit, kBaseLevelContexts> greater_than_one{};
  std::array<AdaptiveBit, kBaseLevelContexts> greater_than_two{};
  std::array<AdaptiveBit, kRangeContexts> level_range{};
};

// Calls f on every context of the set, in the order of the members above (arrays in
// index order): the order of the trained initial probabilities (docs/codec.md 6.1).
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
}

// One decoded non-zero level: natural position and value.
struct BlockLevel {
  uint8_t position;
  int16_t level;
};

// Magnitudes of the coefficients coded so far, in natural order with a zero border two
// wide to the right and below, so the context templates need no bounds checks. Each
// position's significance template (docs/codec.md 3.4) is kept as a running sum: setting
// a magnitude adds it to the positions whose template holds it, so a significance
// context, needed at every coefficient, is one load, and the work falls on the non-zero
// ones. set() is called at most once per position.
class NeighbourMagnitudes {
 public:
  explicit NeighbourMagnitudes(const ScanOrder& order) : stride_(order.width + 2), sum_lead_(2 * stride_ + 2) {
    std::fill_n(grid_.begin(), stride_ * (order.height + 2), uint16_t{0});
    std::fill_n(sum_storage_.begin(), stride_ * (order.height + 2) + 2, uint8_t{0});
  }
  void set(const PositionContext& p, int magnitude) {
    const int cell = p.grid, s = stride_;
    grid_[cell] = static_cast<uint16_t>(magnitude);
    // The positions left of and above this one, whose templates reach it; those outside
    // the block land in the storage's lead or its unread border column.
    const auto capped = static_cast<uint8_t>(std::min(magnitude, 3));
    uint8_t* sums = sum_storage_.data() + sum_lead_ + cell;
    sums[-1] += capped;
    sums[-2] += capped;
    sums[-s] += capped;
    sums[-s - 1] += capped;
    sums[-2 * s] += capped;
  }
  // Contexts of a position (docs/codec.md 3.4).
  int significance_context(const PositionContext& p) const {
    return p.position_class * kNeighbourhoods +
           std::min((sum_storage_[static_cast<size_t>(sum_lead_ + p.grid)] + 1) >> 1, kNeighbourhoods - 1);
  }
  int range_context(const PositionContext& p) const;
  int rice_parameter(const PositionContext& p) const;

 private:
  static constexpr int kMaxStride = kMaxTransformWidth + 2;

  int stride_;
  int sum_lead_;
  std::array<uint16_t, kMaxStride * kMaxStride> grid_;
  // Per cell of grid_, the sum of min(magnitude, 3) over its template (at most 15),
  // after a lead of two rows and two cells that set() writes into and nothing reads.
  std::array<uint8_t, kMaxStride*(kMaxStride + 2) + 2> sum_storage_;
};

// The greater-than-1/2 context of the last significant coefficient (its neighbours to the
// right and below are all zero, and its significance is implied): one per position class
// (0 for the DC, 1 for row + column <= 2, 2 up to 5, 3 beyond).
inline int last_level_context(const PositionContext& p) { return kSignificanceContexts + p.position_class; }

// The end-of-block class of eob in [1, 256]: 0 for 1, 1 for 2, then c for
// 2^(c-1) < eob <= 2^c; and the first eob of a class.
inline int end_of_block_class(int eob) {
  return eob <= 2 ? eob - 1 : std::bit_width(static_cast<unsigned>(eob - 1));
}
inline int class_first_eob(int eob_class) { return eob_class < 2 ? eob_class + 1 : (1 << (eob_class - 1)) + 1; }

}  // namespace svc::codec
