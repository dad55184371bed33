#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <vector>

#include "codec/block_coder.h"
#include "codec/quant.h"
#include "codec/range_coder.h"

namespace svc::codec {
namespace {

TEST(CodecRangeCoder, RoundTripsMixedModelledAndBypassBits) {
  std::mt19937 rng(21);
  struct Symbol {
    int kind;  // 0..7: model index, 8: bypass
    int bit;
  };
  std::vector<Symbol> symbols;
  // Each model has its own skew so the coder adapts to different probabilities.
  for (int n = 0; n < 200000; ++n) {
    const int kind = static_cast<int>(rng() % 9);
    const uint32_t threshold = kind == 8 ? 0x80000000u : static_cast<uint32_t>((kind + 1) * 0x1C000000u);
    symbols.push_back({kind, rng() < threshold ? 1 : 0});
  }
  std::vector<uint8_t> bytes;
  {
    RangeEncoder encoder(&bytes);
    AdaptiveBit models[8];
    for (const Symbol& s : symbols) {
      if (s.kind == 8) {
        encoder.encode_bypass(s.bit);
      } else {
        encoder.encode(models[s.kind], s.bit);
      }
    }
    encoder.finish();
  }
  RangeDecoder decoder(bytes);
  AdaptiveBit models[8];
  for (size_t i = 0; i < symbols.size(); ++i) {
    const Symbol& s = symbols[i];
    const int bit = s.kind == 8 ? decoder.decode_bypass() : decoder.decode(models[s.kind]);
    ASSERT_EQ(bit, s.bit) << "symbol " << i;
  }
  EXPECT_EQ(decoder.overrun(), 0u);
  EXPECT_EQ(decoder.consumed(), bytes.size());
}

TEST(CodecRangeCoder, SkewedBitsCompressNearTheirEntropy) {
  std::mt19937 rng(22);
  const int count = 100000;
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  AdaptiveBit model;
  int ones = 0;
  for (int n = 0; n < count; ++n) {
    const int bit = rng() % 20 == 0;  // p(1) = 0.05: entropy 0.286 bits
    ones += bit;
    encoder.encode(model, bit);
  }
  encoder.finish();
  const double bits_per_symbol = bytes.size() * 8.0 / count;
  EXPECT_LT(bits_per_symbol, 0.286 * 1.06);
  EXPECT_GT(ones, 0);
}

TEST(CodecRangeCoder, EmptyAndShortInputDecodeWithoutReadingOutside) {
  std::vector<uint8_t> empty;
  RangeDecoder decoder(empty);
  AdaptiveBit model;
  for (int i = 0; i < 1000; ++i) {
    decoder.decode(model);
    decoder.decode_bypass();
  }
  EXPECT_GT(decoder.overrun(), 0u);
  EXPECT_EQ(decoder.consumed(), 0u);
}

TEST(CodecExpGolomb, RoundTripsValuesUpTo16Bits) {
  std::vector<uint32_t> values;
  for (uint32_t v = 0; v < 300; ++v) values.push_back(v);
  for (uint32_t v : {1000u, 4095u, 4096u, 65535u, 65536u, 131069u}) values.push_back(v);
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  for (uint32_t v : values) encode_exp_golomb_bypass(encoder, v);
  encoder.finish();
  RangeDecoder decoder(bytes);
  for (uint32_t v : values) {
    uint32_t got = 0;
    ASSERT_TRUE(decode_exp_golomb_bypass(decoder, &got));
    ASSERT_EQ(got, v);
  }
  // A run of 1 bits longer than any valid prefix is rejected.
  std::vector<uint8_t> long_prefix;
  RangeEncoder prefix_encoder(&long_prefix);
  for (int i = 0; i < 40; ++i) prefix_encoder.encode_bypass(1);
  prefix_encoder.finish();
  RangeDecoder bad(long_prefix);
  uint32_t value = 0;
  EXPECT_FALSE(decode_exp_golomb_bypass(bad, &value));
}

// A random block whose non-zero levels thin out with scan position, like real data.
void random_block(std::mt19937& rng, int first_scan, int16_t* levels) {
  for (int i = 0; i < 64; ++i) levels[i] = 0;
  const int style = static_cast<int>(rng() % 6);
  if (style == 0) return;  // empty
  for (int i = first_scan; i < 64; ++i) {
    const uint32_t chance = style == 5 ? 100 : 60 - std::min(55, i);
    if (rng() % 100 < chance) {
      int magnitude = 1 + static_cast<int>(rng() % 3);
      if (rng() % 10 == 0) magnitude = 1 + static_cast<int>(rng() % 40);
      if (rng() % 200 == 0) magnitude = 1 + static_cast<int>(rng() % kMaxLevel);
      levels[kZigZag[i]] = static_cast<int16_t>(rng() & 1 ? -magnitude : magnitude);
    }
  }
  if (style == 4) levels[kZigZag[63]] = kMaxLevel;  // the implied last position
}

TEST(CodecBlockCoder, RoundTripsRandomBlocksAndDcDifferences) {
  std::mt19937 rng(23);
  struct Coded {
    int16_t levels[64];
    int first_scan;
    int cbf_context;
    int dc_difference;
  };
  std::vector<Coded> blocks(3000);
  for (Coded& b : blocks) {
    b.first_scan = rng() % 2 ? 1 : 0;
    random_block(rng, b.first_scan, b.levels);
    bool any = false;
    for (int i = b.first_scan; i < 64; ++i) any = any || b.levels[kZigZag[i]] != 0;
    b.cbf_context = any && rng() % 4 == 0 ? kNoCodedBlockFlag : static_cast<int>(rng() % kCodedBlockContexts);
    b.dc_difference = static_cast<int>(rng() % 41) - 20;
    if (rng() % 50 == 0) b.dc_difference = (rng() & 1 ? 1 : -1) * static_cast<int>(rng() % (2 * kMaxLevel + 1));
  }
  std::vector<uint8_t> bytes;
  {
    RangeEncoder encoder(&bytes);
    BlockContextSet a, b;
    for (size_t n = 0; n < blocks.size(); ++n) {
      BlockContextSet& set = n % 3 == 0 ? a : b;
      encode_dc_difference(encoder, set, blocks[n].dc_difference);
      encode_block_levels(encoder, set, blocks[n].levels, blocks[n].first_scan, blocks[n].cbf_context);
    }
    encoder.finish();
  }
  RangeDecoder decoder(bytes);
  BlockContextSet a, b;
  for (size_t n = 0; n < blocks.size(); ++n) {
    BlockContextSet& set = n % 3 == 0 ? a : b;
    int dc = 0;
    ASSERT_TRUE(decode_dc_difference(decoder, set, &dc));
    ASSERT_EQ(dc, blocks[n].dc_difference) << "block " << n;
    BlockLevel out[64];
    int count = -1;
    ASSERT_TRUE(decode_block_levels(decoder, set, blocks[n].first_scan, blocks[n].cbf_context, out, &count));
    int16_t decoded[64] = {};
    int previous_scan = -1;
    for (int i = 0; i < count; ++i) {
      decoded[out[i].position] = out[i].level;
      int scan = 0;
      while (kZigZag[scan] != out[i].position) ++scan;
      ASSERT_GT(scan, previous_scan) << "levels come in scan order";
      previous_scan = scan;
    }
    for (int i = 0; i < blocks[n].first_scan; ++i) decoded[kZigZag[i]] = blocks[n].levels[kZigZag[i]];
    for (int i = 0; i < 64; ++i) ASSERT_EQ(decoded[i], blocks[n].levels[i]) << "block " << n << " pos " << i;
  }
  EXPECT_EQ(decoder.overrun(), 0u);
  EXPECT_EQ(decoder.consumed(), bytes.size());
}

TEST(CodecBlockCoder, GarbageInputYieldsBoundedLevelsOrErrors) {
  std::mt19937 rng(24);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<uint8_t> garbage(rng() % 200);
    for (auto& v : garbage) v = static_cast<uint8_t>(rng());
    RangeDecoder decoder(garbage);
    BlockContextSet set;
    for (int n = 0; n < 100; ++n) {
      int dc = 0;
      ASSERT_TRUE(decode_dc_difference(decoder, set, &dc));
      ASSERT_LT(std::abs(dc), 1 << kMaxDcCategory);
      BlockLevel out[64];
      int count = 0;
      if (!decode_block_levels(decoder, set, static_cast<int>(n % 2), static_cast<int>(n % 3), out, &count)) break;
      ASSERT_LE(count, 64);
      for (int i = 0; i < count; ++i) {
        ASSERT_LT(out[i].position, 64);
        ASSERT_NE(out[i].level, 0);
        ASSERT_LE(std::abs(out[i].level), kMaxLevel);
      }
    }
  }
}

}  // namespace
}  // namespace svc::codec
