#include "codec/block_coder.h"

#include <algorithm>
#include <bit>
#include <cstdlib>

#include "codec/quant.h"

namespace svc::codec {

const std::array<uint8_t, 64> kZigZag = {
    0,  1,  8,  16, 9,  2,  3,  10, 17, 24, 32, 25, 18, 11, 4,  5,   //
    12, 19, 26, 33, 40, 48, 41, 34, 27, 20, 13, 6,  7,  14, 21, 28,  //
    35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23, 30, 37, 44, 51,  //
    58, 59, 52, 45, 38, 31, 39, 46, 53, 60, 61, 54, 47, 55, 62, 63,  //
};

namespace {

constexpr int kLevelPrefixBins = 14;  // unary bins of |level| - 1 before the escape
constexpr int kMaxExpGolombPrefix = 16;

inline int greater_one_context(int count_greater_one, int count_equal_one) {
  return count_greater_one != 0 ? 0 : std::min(4, 1 + count_equal_one);
}

inline int dc_context_row(int previous_category) {
  return previous_category == 0 ? 0 : (previous_category <= 2 ? 1 : 2);
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

bool decode_exp_golomb_bypass(RangeDecoder& decoder, uint32_t* value) {
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

void encode_block_levels(RangeEncoder& encoder, BlockContextSet& contexts, const int16_t* levels, int first_scan,
                         int coded_block_context) {
  int last_scan = -1;
  for (int i = 63; i >= first_scan; --i) {
    if (levels[kZigZag[i]] != 0) {
      last_scan = i;
      break;
    }
  }
  if (coded_block_context >= 0) {
    encoder.encode(contexts.coded_block[coded_block_context], last_scan >= 0);
    if (last_scan < 0) return;
  }
  // Significance map; position 63 is implied when no earlier "last" was sent.
  for (int i = first_scan; i < 63; ++i) {
    const int significant = levels[kZigZag[i]] != 0;
    encoder.encode(contexts.significant[i], significant);
    if (significant) {
      const int is_last = i == last_scan;
      encoder.encode(contexts.last[i], is_last);
      if (is_last) break;
    }
  }
  // Magnitudes and signs in reverse scan order.
  int count_greater_one = 0, count_equal_one = 0;
  for (int i = last_scan; i >= first_scan; --i) {
    const int level = levels[kZigZag[i]];
    if (level == 0) continue;
    const int magnitude_minus_one = std::abs(level) - 1;
    encoder.encode(contexts.greater_than_one[greater_one_context(count_greater_one, count_equal_one)],
                   magnitude_minus_one > 0);
    if (magnitude_minus_one > 0) {
      AdaptiveBit& remainder = contexts.level_remainder[std::min(4, count_greater_one)];
      int k = 1;
      for (; k < kLevelPrefixBins; ++k) {
        const int more = magnitude_minus_one > k;
        encoder.encode(remainder, more);
        if (!more) break;
      }
      if (k == kLevelPrefixBins) {
        encode_exp_golomb_bypass(encoder, static_cast<uint32_t>(magnitude_minus_one - kLevelPrefixBins));
      }
      ++count_greater_one;
    } else {
      ++count_equal_one;
    }
    encoder.encode_bypass(level < 0);
  }
}

bool decode_block_levels(RangeDecoder& decoder, BlockContextSet& contexts, int first_scan, int coded_block_context,
                         BlockLevel* out, int* count) {
  *count = 0;
  if (first_scan < 0 || first_scan > 63) return false;
  if (coded_block_context >= 0 && !decoder.decode(contexts.coded_block[coded_block_context])) {
    return true;
  }
  int n = 0;
  bool ended = false;
  for (int i = first_scan; i < 63; ++i) {
    if (decoder.decode(contexts.significant[i])) {
      out[n++].position = static_cast<uint8_t>(i);  // scan index for now
      if (decoder.decode(contexts.last[i])) {
        ended = true;
        break;
      }
    }
  }
  if (!ended) out[n++].position = 63;
  int count_greater_one = 0, count_equal_one = 0;
  for (int j = n - 1; j >= 0; --j) {
    int magnitude = 1;
    if (decoder.decode(contexts.greater_than_one[greater_one_context(count_greater_one, count_equal_one)])) {
      AdaptiveBit& remainder = contexts.level_remainder[std::min(4, count_greater_one)];
      int k = 1;
      for (; k < kLevelPrefixBins; ++k) {
        if (!decoder.decode(remainder)) break;
      }
      magnitude = k + 1;
      if (k == kLevelPrefixBins) {
        uint32_t escape = 0;
        if (!decode_exp_golomb_bypass(decoder, &escape)) return false;
        if (escape > static_cast<uint32_t>(kMaxLevel)) return false;
        magnitude += static_cast<int>(escape);
      }
      if (magnitude > kMaxLevel) return false;
      ++count_greater_one;
    } else {
      ++count_equal_one;
    }
    const int negative = decoder.decode_bypass();
    out[j].level = static_cast<int16_t>(negative ? -magnitude : magnitude);
    out[j].position = kZigZag[out[j].position];
  }
  *count = n;
  return true;
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
