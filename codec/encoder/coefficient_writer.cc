// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/coefficient_writer.h"

#include <algorithm>
#include <cstdlib>

#include "codec/encoder/bit_cost.h"

namespace svc::codec {
namespace {

int last_scan_of(const ScanOrder& order, const int16_t* levels) {
  for (int i = order.count - 1; i >= 0; --i) {
    if (levels[order.scan[i]] != 0) return i;
  }
  return -1;
}

// The syntax writers, shared by the encoder (EncodeSink) and the encoder's bit
// estimates (CostSink), so the two cannot drift apart.
struct EncodeSink {
  RangeEncoder& encoder;
  void bit(AdaptiveBit& model, int bit) { encoder.encode(model, bit); }
  void bypass(int bit) { encoder.encode_bypass(bit); }
  void exp_golomb(uint32_t value) { encode_exp_golomb_bypass(encoder, value); }
};

struct CostSink {
  float bits = 0;
  void bit(const AdaptiveBit& model, int bit) { bits += bit_cost(model, bit); }
  void bypass(int) { bits += 1; }
  void exp_golomb(uint32_t value) { bits += exp_golomb_bits(value); }
};

template <class Sink, class Set>
void write_end_of_block(Sink& sink, Set& contexts, const ScanOrder& order, TransformSize size, int last_scan) {
  const size_t s = static_cast<size_t>(size);
  const int eob = last_scan + 1;
  const int eob_class = end_of_block_class(eob), max_class = end_of_block_class(order.count);
  for (int j = 0; j < eob_class; ++j) sink.bit(contexts.eob_class[s][j], 1);
  if (eob_class < max_class) sink.bit(contexts.eob_class[s][eob_class], 0);
  if (eob_class < 2) return;
  const int extra_bits = eob_class - 1, offset = eob - class_first_eob(eob_class);
  sink.bit(contexts.eob_extra[s][eob_class], (offset >> (extra_bits - 1)) & 1);
  for (int b = extra_bits - 2; b >= 0; --b) sink.bypass((offset >> b) & 1);
}

template <class Sink, class Set>
void write_magnitude(Sink& sink, Set& contexts, const NeighbourMagnitudes& neighbours,
                     const PositionContext& position, int base_context, int magnitude) {
  sink.bit(contexts.greater_than_one[base_context], magnitude > 1);
  if (magnitude == 1) return;
  sink.bit(contexts.greater_than_two[base_context], magnitude > 2);
  if (magnitude == 2) return;
  auto& range = contexts.level_range[neighbours.range_context(position)];
  for (int k = 3; k < kRangeLevel; ++k) {
    sink.bit(range, magnitude > k);
    if (magnitude == k) return;
  }
  const int rice = neighbours.rice_parameter(position);
  const auto remainder = static_cast<uint32_t>(magnitude - kRangeLevel);
  sink.exp_golomb(remainder >> rice);
  for (int b = rice - 1; b >= 0; --b) sink.bypass((remainder >> b) & 1);
}

template <class Sink, class Set>
void write_levels(Sink& sink, Set& contexts, const int16_t* levels, int coded_block_context, TransformSize size) {
  const ScanOrder& order = scan_order(size);
  const int last_scan = last_scan_of(order, levels);
  if (coded_block_context >= 0) sink.bit(contexts.coded_block[coded_block_context], last_scan >= 0);
  if (last_scan < 0) return;
  write_end_of_block(sink, contexts, order, size, last_scan);
  NeighbourMagnitudes neighbours(order);
  for (int i = last_scan; i >= 0; --i) {
    const PositionContext& entry = order.scanned[i];
    const int position = entry.position, level = levels[position], magnitude = std::abs(level);
    int base_context = last_level_context(entry);
    if (i != last_scan) {
      base_context = neighbours.significance_context(entry);
      sink.bit(contexts.significant[base_context], magnitude != 0);
      if (magnitude == 0) continue;
    }
    write_magnitude(sink, contexts, neighbours, entry, base_context, magnitude);
    sink.bypass(level < 0);
    neighbours.set(entry, magnitude);
  }
}
}  // namespace

void encode_exp_golomb_bypass(RangeEncoder& encoder, uint32_t value) {
  int bits = 0;
  while (value >= (1u << bits)) {
    encoder.encode_bypass(1);
    value -= 1u << bits;
    ++bits;
  }
  encoder.encode_bypass(0);
  while (bits-- > 0) encoder.encode_bypass(static_cast<int>((value >> bits) & 1));
}

void encode_block_levels(RangeEncoder& encoder, BlockContextSet& contexts, const int16_t* levels,
                         int coded_block_context, TransformSize size) {
  const SyntaxScope scope(encoder, SyntaxElement::kLevels);
  EncodeSink sink{encoder};
  write_levels(sink, contexts, levels, coded_block_context, size);
}

float block_levels_bits(const BlockContextSet& contexts, const int16_t* levels, int coded_block_context,
                        TransformSize size) {
  CostSink sink;
  write_levels(sink, contexts, levels, coded_block_context, size);
  return sink.bits;
}

float uncoded_block_bits(const BlockContextSet& contexts, int coded_block_context) {
  CostSink sink;
  if (coded_block_context >= 0) sink.bit(contexts.coded_block[coded_block_context], 0);
  return sink.bits;
}

EndOfBlockPricer::EndOfBlockPricer(const BlockContextSet& contexts, TransformSize size)
    : extra_(contexts.eob_extra[static_cast<size_t>(size)].data()) {
  const auto& classes = contexts.eob_class[static_cast<size_t>(size)];
  const int max_class = end_of_block_class(scan_order(size).count);
  float unary = 0;  // the sum CostSink forms over the leading 1 bits
  for (int c = 0; c <= max_class; ++c) {
    class_bits_[static_cast<size_t>(c)] = c < max_class ? unary + bit_cost(classes[c], 0) : unary;
    if (c < max_class) unary += bit_cost(classes[c], 1);
  }
}

float EndOfBlockPricer::bits(int last_scan) const {
  const int eob = last_scan + 1, eob_class = end_of_block_class(eob);
  float bits = class_bits_[static_cast<size_t>(eob_class)];
  if (eob_class < 2) return bits;
  const int extra_bits = eob_class - 1, offset = eob - class_first_eob(eob_class);
  bits += bit_cost(extra_[eob_class], (offset >> (extra_bits - 1)) & 1);
  for (int b = extra_bits - 2; b >= 0; --b) bits += 1;
  return bits;
}

float magnitude_bits(const BlockContextSet& contexts, const NeighbourMagnitudes& neighbours,
                     const PositionContext& position, int base_context, int magnitude) {
  CostSink sink;
  write_magnitude(sink, contexts, neighbours, position, base_context, magnitude);
  return sink.bits + 1;  // sign
}

}  // namespace svc::codec
