// SPDX-License-Identifier: BSD-2-Clause
#include "codec/decoder/coefficient_reader.h"

#include <algorithm>

#include "codec/common/quant.h"

namespace svc::codec {
namespace {

inline bool read_exp_golomb(RangeDecoder& decoder, uint32_t* value) {
  constexpr int kMaxExpGolombPrefix = 16;
  int bits = 0;
  uint32_t base = 0;
  while (decoder.decode_bypass()) {
    base += 1u << bits;
    if (++bits > kMaxExpGolombPrefix) return false;
  }
  uint32_t suffix = 0;
  for (int i = 0; i < bits; ++i) suffix = (suffix << 1) | static_cast<uint32_t>(decoder.decode_bypass());
  *value = base + suffix;
  return true;
}

// Returns 0 on invalid syntax, else the end-of-block count (last scan + 1).
int read_end_of_block(RangeDecoder& decoder, BlockContextSet& contexts, const ScanOrder& order,
                      TransformSize size) {
  const size_t s = static_cast<size_t>(size);
  const int max_eob = order.count, max_class = end_of_block_class(max_eob);
  int eob_class = 0;
  while (eob_class < max_class && decoder.decode(contexts.eob_class[s][eob_class])) ++eob_class;
  if (eob_class < 2) return eob_class + 1;
  const int extra_bits = eob_class - 1;
  int offset = decoder.decode(contexts.eob_extra[s][eob_class]);
  for (int b = extra_bits - 2; b >= 0; --b) offset = (offset << 1) | decoder.decode_bypass();
  const int eob = class_first_eob(eob_class) + offset;
  return eob <= max_eob ? eob : 0;
}

bool read_magnitude(RangeDecoder& decoder, BlockContextSet& contexts, const NeighbourMagnitudes& neighbours,
                    const PositionContext& position, int base_context, int* magnitude) {
  *magnitude = 1;
  if (!decoder.decode(contexts.greater_than_one[base_context])) return true;
  *magnitude = 2;
  if (!decoder.decode(contexts.greater_than_two[base_context])) return true;
  AdaptiveBit& range = contexts.level_range[neighbours.range_context(position)];
  for (int k = 3; k < kRangeLevel; ++k) {
    *magnitude = k;
    if (!decoder.decode(range)) return true;
  }
  uint32_t quotient = 0;
  if (!read_exp_golomb(decoder, &quotient) || quotient > static_cast<uint32_t>(kMaxLevel)) return false;
  const int rice = neighbours.rice_parameter(position);
  uint32_t remainder = quotient;
  for (int b = 0; b < rice; ++b) remainder = (remainder << 1) | static_cast<uint32_t>(decoder.decode_bypass());
  if (remainder > static_cast<uint32_t>(kMaxLevel - kRangeLevel)) return false;
  *magnitude = kRangeLevel + static_cast<int>(remainder);
  return true;
}

[[gnu::always_inline]] inline bool read_levels(RangeDecoder& decoder, BlockContextSet& contexts,
                                               int coded_block_context, BlockLevel* out, int* count,
                                               TransformSize size) {
  *count = 0;
  const ScanOrder& order = scan_order(size);
  if (coded_block_context >= 0 && !decoder.decode(contexts.coded_block[coded_block_context])) return true;
  const int eob = read_end_of_block(decoder, contexts, order, size);
  if (eob == 0) return false;
  const int last_scan = eob - 1;
  NeighbourMagnitudes neighbours(order);
  int n = 0;
  for (int i = last_scan; i >= 0; --i) {
    const PositionContext& entry = order.scanned[i];
    int base_context = last_level_context(entry);
    if (i != last_scan) {
      base_context = neighbours.significance_context(entry);
      if (!decoder.decode(contexts.significant[base_context])) continue;
    }
    int magnitude = 0;
    if (!read_magnitude(decoder, contexts, neighbours, entry, base_context, &magnitude)) return false;
    const int negative = decoder.decode_bypass();
    out[n++] = {entry.position, static_cast<int16_t>(negative ? -magnitude : magnitude)};
    neighbours.set(entry, magnitude);
  }
  std::reverse(out, out + n);
  *count = n;
  return true;
}

}  // namespace

bool decode_exp_golomb_bypass(RangeDecoder& decoder, uint32_t* value) { return read_exp_golomb(decoder, value); }

bool decode_block_levels(RangeDecoder& shared_decoder, BlockContextSet& contexts, int coded_block_context,
                         BlockLevel* out, int* count, TransformSize size) {
  // A local copy the compiler can keep in registers: byte stores through `out` and the
  // contexts could otherwise alias the decoder's state.
  RangeDecoder decoder = shared_decoder;
  const bool valid = read_levels(decoder, contexts, coded_block_context, out, count, size);
  shared_decoder = decoder;
  return valid;
}

}  // namespace svc::codec
