#include "codec/common/block_coder.h"

#include <algorithm>
#include <bit>
#include <cstdlib>

#include "codec/common/bframe_syntax.h"
#include "codec/common/quant.h"

namespace svc::codec {

const std::array<uint8_t, 64> kZigZag = {
    0,  1,  8,  16, 9,  2,  3,  10, 17, 24, 32, 25, 18, 11, 4,  5,   //
    12, 19, 26, 33, 40, 48, 41, 34, 27, 20, 13, 6,  7,  14, 21, 28,  //
    35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23, 30, 37, 44, 51,  //
    58, 59, 52, 45, 38, 31, 39, 46, 53, 60, 61, 54, 47, 55, 62, 63,  //
};

namespace {

// The zig-zag of an N x N block: anti-diagonals in increasing order, odd ones from the
// top right down, even ones from the bottom left up (MPEG-2's order for N = 8).
template <int W, int H = W>
constexpr std::array<uint8_t, W * H> zig_zag() {
  std::array<uint8_t, W * H> scan{};
  int i = 0;
  for (int d = 0; d <= W + H - 2; ++d) {
    for (int k = 0; k <= d; ++k) {
      const int row = d % 2 ? k : d - k, column = d - row;
      if (row < H && column < W) scan[static_cast<size_t>(i++)] = static_cast<uint8_t>(W * row + column);
    }
  }
  return scan;
}
constexpr std::array<uint8_t, 16> kZigZag4x4 = zig_zag<4>();
constexpr std::array<uint8_t, 256> kZigZag16x16 = zig_zag<16>();
constexpr std::array<uint8_t, 128> kZigZag16x8 = zig_zag<16, 8>();
constexpr std::array<uint8_t, 128> kZigZag8x16 = zig_zag<8, 16>();
constexpr std::array<uint8_t, 64> kZigZag16x4 = zig_zag<16, 4>();
constexpr std::array<uint8_t, 64> kZigZag4x16 = zig_zag<4, 16>();
constexpr std::array<uint8_t, 32> kZigZag8x4 = zig_zag<8, 4>();
constexpr std::array<uint8_t, 32> kZigZag4x8 = zig_zag<4, 8>();

constexpr int diagonal_class(int row, int column) {
  const int diagonal = row + column;
  return diagonal == 0 ? 0 : diagonal <= 2 ? 1 : diagonal <= 5 ? 2 : 3;
}

template <int W, int H = W>
constexpr std::array<PositionContext, W * H> position_contexts() {
  std::array<PositionContext, W * H> table{};
  for (int row = 0; row < H; ++row) {
    for (int column = 0; column < W; ++column) {
      PositionContext& entry = table[static_cast<size_t>(row * W + column)];
      entry.grid = static_cast<uint16_t>(row * (W + 2) + column);
      entry.position_class = static_cast<uint8_t>(diagonal_class(row, column));
      entry.range_group = static_cast<uint8_t>(row + column == 0 ? 0 : (row < 2 && column < 2 ? 1 : 2));
    }
  }
  return table;
}
constexpr std::array<PositionContext, 16> kPositions4x4 = position_contexts<4>();
constexpr std::array<PositionContext, 64> kPositions8x8 = position_contexts<8>();
constexpr std::array<PositionContext, 256> kPositions16x16 = position_contexts<16>();
constexpr std::array<PositionContext, 128> kPositions16x8 = position_contexts<16, 8>();
constexpr std::array<PositionContext, 128> kPositions8x16 = position_contexts<8, 16>();
constexpr std::array<PositionContext, 64> kPositions16x4 = position_contexts<16, 4>();
constexpr std::array<PositionContext, 64> kPositions4x16 = position_contexts<4, 16>();
constexpr std::array<PositionContext, 32> kPositions8x4 = position_contexts<8, 4>();
constexpr std::array<PositionContext, 32> kPositions4x8 = position_contexts<4, 8>();

constexpr ScanOrder kScan8x8{8, 8, 64, kZigZag.data(), kPositions8x8.data()};
constexpr ScanOrder kScan4x4{4, 4, 16, kZigZag4x4.data(), kPositions4x4.data()};
constexpr ScanOrder kScan16x16{16, 16, 256, kZigZag16x16.data(), kPositions16x16.data()};
constexpr ScanOrder kScan16x8{16, 8, 128, kZigZag16x8.data(), kPositions16x8.data()};
constexpr ScanOrder kScan8x16{8, 16, 128, kZigZag8x16.data(), kPositions8x16.data()};
constexpr ScanOrder kScan16x4{16, 4, 64, kZigZag16x4.data(), kPositions16x4.data()};
constexpr ScanOrder kScan4x16{4, 16, 64, kZigZag4x16.data(), kPositions4x16.data()};
constexpr ScanOrder kScan8x4{8, 4, 32, kZigZag8x4.data(), kPositions8x4.data()};
constexpr ScanOrder kScan4x8{4, 8, 32, kZigZag4x8.data(), kPositions4x8.data()};

// eob in [1, 256]: 0 for 1, 1 for 2, then c for 2^(c-1) < eob <= 2^c.
int end_of_block_class(int eob) { return eob <= 2 ? eob - 1 : std::bit_width(static_cast<unsigned>(eob - 1)); }
int class_first_eob(int eob_class) { return eob_class < 2 ? eob_class + 1 : (1 << (eob_class - 1)) + 1; }

int last_scan_of(const ScanOrder& order, const int16_t* levels, int first_scan) {
  for (int i = order.count - 1; i >= first_scan; --i) {
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
  void bit(const AdaptiveBit& model, int bit) { bits += bframe::bit_cost(model, bit); }
  void bypass(int) { bits += 1; }
  void exp_golomb(uint32_t value) { bits += bframe::exp_golomb_bits(value); }
};

template <class Sink, class Set>
void write_end_of_block(Sink& sink, Set& contexts, const ScanOrder& order, TransformSize size, int first_scan,
                        int last_scan) {
  const size_t s = static_cast<size_t>(size);
  const int eob = last_scan - first_scan + 1;
  const int eob_class = end_of_block_class(eob), max_class = end_of_block_class(order.count - first_scan);
  for (int j = 0; j < eob_class; ++j) sink.bit(contexts.eob_class[s][j], 1);
  if (eob_class < max_class) sink.bit(contexts.eob_class[s][eob_class], 0);
  if (eob_class < 2) return;
  const int extra_bits = eob_class - 1, offset = eob - class_first_eob(eob_class);
  sink.bit(contexts.eob_extra[s][eob_class], (offset >> (extra_bits - 1)) & 1);
  for (int b = extra_bits - 2; b >= 0; --b) sink.bypass((offset >> b) & 1);
}

template <class Sink, class Set>
void write_magnitude(Sink& sink, Set& contexts, const NeighbourMagnitudes& neighbours, int position,
                     int base_context, int magnitude) {
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
void write_levels(Sink& sink, Set& contexts, const int16_t* levels, int first_scan, int coded_block_context,
                  TransformSize size) {
  const ScanOrder& order = scan_order(size);
  const int last_scan = last_scan_of(order, levels, first_scan);
  if (coded_block_context >= 0) sink.bit(contexts.coded_block[coded_block_context], last_scan >= 0);
  if (last_scan < 0) return;
  write_end_of_block(sink, contexts, order, size, first_scan, last_scan);
  NeighbourMagnitudes neighbours(order);
  for (int i = last_scan; i >= first_scan; --i) {
    const int position = order.scan[i], level = levels[position], magnitude = std::abs(level);
    int base_context = last_level_context(order, position);
    if (i != last_scan) {
      base_context = neighbours.significance_context(position);
      sink.bit(contexts.significant[base_context], magnitude != 0);
      if (magnitude == 0) continue;
    }
    write_magnitude(sink, contexts, neighbours, position, base_context, magnitude);
    sink.bypass(level < 0);
    neighbours.set(position, magnitude);
  }
}

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

// Returns 0 on invalid syntax, else the end-of-block count (last scan - first_scan + 1).
int read_end_of_block(RangeDecoder& decoder, BlockContextSet& contexts, const ScanOrder& order, TransformSize size,
                      int first_scan) {
  const size_t s = static_cast<size_t>(size);
  const int max_eob = order.count - first_scan, max_class = end_of_block_class(max_eob);
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
                    int position, int base_context, int* magnitude) {
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

inline int dc_context_row(int previous_category) {
  return previous_category == 0 ? 0 : (previous_category <= 2 ? 1 : 2);
}

[[gnu::always_inline]] inline bool read_levels(RangeDecoder& decoder, BlockContextSet& contexts, int first_scan,
                                               int coded_block_context, BlockLevel* out, int* count,
                                               TransformSize size) {
  *count = 0;
  const ScanOrder& order = scan_order(size);
  if (first_scan < 0 || first_scan >= order.count) return false;
  if (coded_block_context >= 0 && !decoder.decode(contexts.coded_block[coded_block_context])) return true;
  const int eob = read_end_of_block(decoder, contexts, order, size, first_scan);
  if (eob == 0) return false;
  const int last_scan = first_scan + eob - 1;
  NeighbourMagnitudes neighbours(order);
  int n = 0;
  for (int i = last_scan; i >= first_scan; --i) {
    const int position = order.scan[i];
    int base_context = last_level_context(order, position);
    if (i != last_scan) {
      base_context = neighbours.significance_context(position);
      if (!decoder.decode(contexts.significant[base_context])) continue;
    }
    int magnitude = 0;
    if (!read_magnitude(decoder, contexts, neighbours, position, base_context, &magnitude)) return false;
    const int negative = decoder.decode_bypass();
    out[n++] = {static_cast<uint8_t>(position), static_cast<int16_t>(negative ? -magnitude : magnitude)};
    neighbours.set(position, magnitude);
  }
  std::reverse(out, out + n);
  *count = n;
  return true;
}

}  // namespace

const ScanOrder& scan_order(TransformSize size) {
  switch (size) {
    case TransformSize::k4x4: return kScan4x4;
    case TransformSize::k16x16: return kScan16x16;
    case TransformSize::k16x8: return kScan16x8;
    case TransformSize::k8x16: return kScan8x16;
    case TransformSize::k16x4: return kScan16x4;
    case TransformSize::k4x16: return kScan4x16;
    case TransformSize::k8x4: return kScan8x4;
    case TransformSize::k4x8: return kScan4x8;
    default: return kScan8x8;
  }
}

int NeighbourMagnitudes::range_context(int position) const {
  const uint16_t* a = grid_.data() + positions_[position].grid;
  const int s = stride_;
  const int magnitude = std::min<int>(a[1], 15) + std::min<int>(a[s], 15) + std::min<int>(a[s + 1], 15);
  return positions_[position].range_group * 7 + std::min((magnitude + 1) >> 1, 6);
}

int NeighbourMagnitudes::rice_parameter(int position) const {
  const uint16_t* a = grid_.data() + positions_[position].grid;
  const int s = stride_;
  const unsigned sum = unsigned{a[1]} + a[s] + a[s + 1] + a[2] + a[2 * s];
  return std::min(kMaxRiceParameter, static_cast<int>(std::bit_width(sum >> 6)));
}

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

bool decode_exp_golomb_bypass(RangeDecoder& decoder, uint32_t* value) { return read_exp_golomb(decoder, value); }

void encode_block_levels(RangeEncoder& encoder, BlockContextSet& contexts, const int16_t* levels, int first_scan,
                         int coded_block_context, TransformSize size) {
  EncodeSink sink{encoder};
  write_levels(sink, contexts, levels, first_scan, coded_block_context, size);
}

float block_levels_bits(const BlockContextSet& contexts, const int16_t* levels, int first_scan,
                        int coded_block_context, TransformSize size) {
  CostSink sink;
  write_levels(sink, contexts, levels, first_scan, coded_block_context, size);
  return sink.bits;
}

float uncoded_block_bits(const BlockContextSet& contexts, int coded_block_context) {
  CostSink sink;
  if (coded_block_context >= 0) sink.bit(contexts.coded_block[coded_block_context], 0);
  return sink.bits;
}

EndOfBlockPricer::EndOfBlockPricer(const BlockContextSet& contexts, int first_scan, TransformSize size)
    : extra_(contexts.eob_extra[static_cast<size_t>(size)].data()), first_scan_(first_scan) {
  const auto& classes = contexts.eob_class[static_cast<size_t>(size)];
  const int max_class = end_of_block_class(scan_order(size).count - first_scan);
  float unary = 0;  // the sum CostSink forms over the leading 1 bits
  for (int c = 0; c <= max_class; ++c) {
    class_bits_[static_cast<size_t>(c)] = c < max_class ? unary + bframe::bit_cost(classes[c], 0) : unary;
    if (c < max_class) unary += bframe::bit_cost(classes[c], 1);
  }
}

float EndOfBlockPricer::bits(int last_scan) const {
  const int eob = last_scan - first_scan_ + 1, eob_class = end_of_block_class(eob);
  float bits = class_bits_[static_cast<size_t>(eob_class)];
  if (eob_class < 2) return bits;
  const int extra_bits = eob_class - 1, offset = eob - class_first_eob(eob_class);
  bits += bframe::bit_cost(extra_[eob_class], (offset >> (extra_bits - 1)) & 1);
  for (int b = extra_bits - 2; b >= 0; --b) bits += 1;
  return bits;
}

float magnitude_bits(const BlockContextSet& contexts, const NeighbourMagnitudes& neighbours, int position,
                     int base_context, int magnitude) {
  CostSink sink;
  write_magnitude(sink, contexts, neighbours, position, base_context, magnitude);
  return sink.bits + 1;  // sign
}

bool decode_block_levels(RangeDecoder& shared_decoder, BlockContextSet& contexts, int first_scan,
                         int coded_block_context, BlockLevel* out, int* count, TransformSize size) {
  // A local copy the compiler can keep in registers: byte stores through `out` and the
  // contexts could otherwise alias the decoder's state.
  RangeDecoder decoder = shared_decoder;
  const bool valid = read_levels(decoder, contexts, first_scan, coded_block_context, out, count, size);
  shared_decoder = decoder;
  return valid;
}

void encode_dc_difference(RangeEncoder& encoder, BlockContextSet& contexts, int difference) {
  const unsigned magnitude = static_cast<unsigned>(std::abs(difference));
  const int category = magnitude == 0 ? 0 : std::bit_width(magnitude);
  auto& row = contexts.dc_category[dc_context_row(contexts.previous_dc_category)];
  for (int i = 0; i < category; ++i) encoder.encode(row[i], 1);
  if (category < kMaxDcCategory) encoder.encode(row[category], 0);
  if (category > 0) {
    encoder.encode_bypass(difference < 0);
    for (int bit = category - 2; bit >= 0; --bit) encoder.encode_bypass((magnitude >> bit) & 1);
  }
  contexts.previous_dc_category = category;
}

bool decode_dc_difference(RangeDecoder& decoder, BlockContextSet& contexts, int* difference) {
  auto& row = contexts.dc_category[dc_context_row(contexts.previous_dc_category)];
  int category = 0;
  while (category < kMaxDcCategory && decoder.decode(row[category])) ++category;
  int value = 0;
  if (category > 0) {
    const int negative = decoder.decode_bypass();
    value = 1;
    for (int bit = category - 2; bit >= 0; --bit) value = (value << 1) | decoder.decode_bypass();
    if (negative) value = -value;
  }
  contexts.previous_dc_category = category;
  *difference = value;
  return true;
}

}  // namespace svc::codec
