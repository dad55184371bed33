// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <random>
#include <span>
#include <vector>

#include "codec/common/coefficient_contexts.h"
#include "codec/common/quant.h"
#include "codec/decoder/coefficient_reader.h"
#include "codec/decoder/range_decoder.h"
#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/range_encoder.h"

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
  EXPECT_LE(decoder.overrun(), kImplicitZeroBytes);  // the final zeros left out
  EXPECT_EQ(decoder.consumed(), bytes.size());
}

// Short streams of every length end without the zeros the decoder supplies itself: the
// last byte is non-zero unless the full kImplicitZeroBytes were left out, the decoder
// reads no more than those past the end, and the zeros written back change nothing.
TEST(CodecRangeCoder, StreamsEndWithoutTheirFinalZeroBytes) {
  std::mt19937 rng(24);
  size_t saved = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<int> bits(static_cast<size_t>(trial % 97));
    for (int& bit : bits) bit = rng() % 5 == 0;
    std::vector<uint8_t> bytes = {0xAB};  // a header before the stream is never trimmed
    {
      RangeEncoder encoder(&bytes);
      AdaptiveBit model;
      for (int bit : bits) encoder.encode(model, bit);
      encoder.finish();
    }
    ASSERT_GE(bytes.size(), 1u);
    EXPECT_EQ(bytes[0], 0xAB);
    const std::span<const uint8_t> stream(bytes.data() + 1, bytes.size() - 1);
    for (size_t padding = 0; padding <= kImplicitZeroBytes; ++padding) {
      std::vector<uint8_t> padded(stream.begin(), stream.end());
      padded.insert(padded.end(), padding, 0);
      RangeDecoder decoder(padded);
      AdaptiveBit model;
      for (size_t i = 0; i < bits.size(); ++i) ASSERT_EQ(decoder.decode(model), bits[i]) << trial << " " << i;
      if (padding == 0) {
        EXPECT_LE(decoder.overrun(), kImplicitZeroBytes) << trial;
        if (decoder.overrun() < kImplicitZeroBytes && !stream.empty()) EXPECT_NE(stream.back(), 0) << trial;
        saved += decoder.overrun();
      }
    }
  }
  EXPECT_GT(saved, 400u * 2) << "the ending saves bytes";
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
void random_block(std::mt19937& rng, int16_t* levels) {
  for (int i = 0; i < 64; ++i) levels[i] = 0;
  const int style = static_cast<int>(rng() % 6);
  if (style == 0) return;  // empty
  for (int i = 0; i < 64; ++i) {
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

TEST(CodecBlockCoder, RoundTripsRandomBlocks) {
  std::mt19937 rng(23);
  struct Coded {
    int16_t levels[64];
    int cbf_context;
  };
  std::vector<Coded> blocks(3000);
  for (Coded& b : blocks) {
    random_block(rng, b.levels);
    bool any = false;
    for (int i = 0; i < 64; ++i) any = any || b.levels[i] != 0;
    b.cbf_context = any && rng() % 4 == 0 ? kNoCodedBlockFlag : static_cast<int>(rng() % kCodedBlockContexts);
  }
  std::vector<uint8_t> bytes;
  {
    RangeEncoder encoder(&bytes);
    BlockContextSet a, b;
    for (size_t n = 0; n < blocks.size(); ++n) {
      BlockContextSet& set = n % 3 == 0 ? a : b;
      encode_block_levels(encoder, set, blocks[n].levels, blocks[n].cbf_context);
    }
    encoder.finish();
  }
  RangeDecoder decoder(bytes);
  BlockContextSet a, b;
  for (size_t n = 0; n < blocks.size(); ++n) {
    BlockContextSet& set = n % 3 == 0 ? a : b;
    BlockLevel out[64];
    int count = -1;
    ASSERT_TRUE(decode_block_levels(decoder, set, blocks[n].cbf_context, out, &count));
    int16_t decoded[64] = {};
    int previous_scan = -1;
    for (int i = 0; i < count; ++i) {
      decoded[out[i].position] = out[i].level;
      int scan = 0;
      while (kZigZag[scan] != out[i].position) ++scan;
      ASSERT_GT(scan, previous_scan) << "levels come in scan order";
      previous_scan = scan;
    }
    for (int i = 0; i < 64; ++i) ASSERT_EQ(decoded[i], blocks[n].levels[i]) << "block " << n << " pos " << i;
  }
  EXPECT_LE(decoder.overrun(), kImplicitZeroBytes);  // the final zeros left out
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
      BlockLevel out[64];
      int count = 0;
      if (!decode_block_levels(decoder, set, static_cast<int>(n % 3), out, &count)) break;
      ASSERT_LE(count, 64);
      for (int i = 0; i < count; ++i) {
        ASSERT_LT(out[i].position, 64);
        ASSERT_NE(out[i].level, 0);
        ASSERT_LE(std::abs(out[i].level), kMaxLevel);
      }
    }
  }
}

// Decodes one block with `set` and returns it in natural order; fails the test on a
// syntax error.
std::array<int16_t, 64> decode_dense(RangeDecoder& decoder, BlockContextSet& set, int cbf_context) {
  std::array<int16_t, 64> dense{};
  BlockLevel out[64];
  int count = -1;
  EXPECT_TRUE(decode_block_levels(decoder, set, cbf_context, out, &count));
  for (int i = 0; i < count; ++i) dense[out[i].position] = out[i].level;
  return dense;
}

TEST(CodecBlockCoder, RoundTripsEveryEndOfBlockAndLevelBoundary) {
  std::vector<std::array<int16_t, 64>> blocks;
  for (int last = 0; last < 64; ++last) {
    std::array<int16_t, 64> levels{};
    levels[kZigZag[last]] = static_cast<int16_t>(last % 2 ? -1 : 2);
    blocks.push_back(levels);
  }
  // Magnitudes at every binarization boundary, with growing neighbours (Rice 0..4).
  for (int magnitude : {1, 2, 3, 14, 15, 16, 30, 31, 100, 1000, 4080, 4094, kMaxLevel}) {
    for (int neighbour : {0, 5, 40, 200, kMaxLevel}) {
      std::array<int16_t, 64> levels{};
      levels[0] = static_cast<int16_t>(-magnitude);
      for (int position : {1, 2, 8, 9, 16}) levels[position] = static_cast<int16_t>(neighbour);
      levels[63] = 1;
      blocks.push_back(levels);
    }
  }
  std::vector<uint8_t> bytes;
  {
    RangeEncoder encoder(&bytes);
    BlockContextSet set;
    for (const auto& levels : blocks) encode_block_levels(encoder, set, levels.data(), 1);
    encoder.finish();
  }
  RangeDecoder decoder(bytes);
  BlockContextSet set;
  for (size_t n = 0; n < blocks.size(); ++n) {
    ASSERT_EQ(decode_dense(decoder, set, 1), blocks[n]) << "block " << n;
  }
  EXPECT_EQ(decoder.consumed(), bytes.size());
}

TEST(CodecBlockCoder, BitEstimateMatchesTheCodedSize) {
  std::mt19937 rng(25);
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  BlockContextSet set;
  double estimated = 0;
  for (int n = 0; n < 4000; ++n) {
    int16_t levels[64];
    random_block(rng, levels);
    const int cbf_context = n % kCodedBlockContexts;
    estimated += block_levels_bits(set, levels, cbf_context);
    encode_block_levels(encoder, set, levels, cbf_context);
  }
  encoder.finish();
  const double coded = 8.0 * static_cast<double>(bytes.size());
  // The estimate holds the contexts fixed over a block while the coder adapts them
  // within it (a few percent on these level-heavy blocks); a binarization that differs
  // would be off by far more.
  EXPECT_NEAR(estimated, coded, coded * 0.04) << "estimated " << estimated << " bits, coded " << coded;
}

TEST(CodecBlockCoder, NeighbourContextsEqualTheTemplateOverTheMagnitudesSet) {
  // The running template sums against docs/codec.md 3.4's derivation from the
  // magnitudes themselves, at every position of every size, as a coder visits them
  // (reverse scan, each set once), with zeros, small and large magnitudes.
  std::mt19937 rng(17);
  for (int s = 0; s < kTransformSizes; ++s) {
    const ScanOrder& order = scan_order(static_cast<TransformSize>(s));
    const int w = order.width, h = order.height;
    for (int trial = 0; trial < 40; ++trial) {
      std::array<int, kMaxTransformArea> magnitude{};  // set so far
      auto a = [&](int r, int c) { return r < h && c < w ? magnitude[static_cast<size_t>(r * w + c)] : 0; };
      NeighbourMagnitudes neighbours(order);
      for (int i = order.count - 1; i >= 0; --i) {
        const int p = order.scan[i], r = p / w, c = p % w;
        const PositionContext& entry = order.scanned[i];
        ASSERT_EQ(entry.position, p);
        const int diagonal = r + c, position_class = diagonal == 0 ? 0 : diagonal <= 2 ? 1 : diagonal <= 5 ? 2 : 3;
        const std::array<int, 5> t = {a(r, c + 1), a(r + 1, c), a(r + 1, c + 1), a(r, c + 2), a(r + 2, c)};
        int m5 = 0, sum = 0;
        for (const int v : t) m5 += std::min(v, 3), sum += v;
        const int m3 = std::min(t[0], 15) + std::min(t[1], 15) + std::min(t[2], 15);
        const int group = p == 0 ? 0 : r < 2 && c < 2 ? 1 : 2;
        ASSERT_EQ(neighbours.significance_context(entry), 5 * position_class + std::min((m5 + 1) >> 1, 4))
            << "size " << s << " position " << p;
        ASSERT_EQ(entry.grid, r * (w + 2) + c);  // its cell of the bordered grid
        ASSERT_EQ(neighbours.range_context(entry), 7 * group + std::min((m3 + 1) >> 1, 6));
        ASSERT_EQ(neighbours.rice_parameter(entry),
                  std::min(4, static_cast<int>(std::bit_width(static_cast<unsigned>(sum) >> 6))));
        const int draw = static_cast<int>(rng() % 8);
        const int value = draw < 4 ? 0 : draw < 7 ? draw - 3 : static_cast<int>(rng() % 400);
        magnitude[static_cast<size_t>(p)] = value;
        neighbours.set(entry, value);
      }
    }
  }
}

TEST(CodecBlockCoder, AnEndOfBlockAtTheLastPositionOfEverySizeRoundTrips) {
  // The end-of-block classes of every size reach exactly its last position.
  for (int s = 0; s < kTransformSizes; ++s) {
    const auto size = static_cast<TransformSize>(s);
    const ScanOrder& order = scan_order(size);
    std::array<int16_t, kMaxTransformArea> levels{};
    levels[order.scan[order.count - 1]] = 1;
    std::vector<uint8_t> bytes;
    RangeEncoder encoder(&bytes);
    BlockContextSet written;
    encode_block_levels(encoder, written, levels.data(), kNoCodedBlockFlag, size);
    encoder.finish();
    RangeDecoder decoder(bytes);
    BlockContextSet set;
    BlockLevel out[kMaxTransformArea];
    int count = 0;
    ASSERT_TRUE(decode_block_levels(decoder, set, kNoCodedBlockFlag, out, &count, size)) << "size " << s;
    ASSERT_EQ(count, 1);
    EXPECT_EQ(out[0].position, order.scan[order.count - 1]);
    EXPECT_EQ(out[0].level, 1);
  }
}

TEST(CodecBlockCoder, RejectsALevelBeyondTheMaximum) {
  for (const uint32_t quotient : {4080u, 4081u, 4096u}) {
    // A DC-only block written bin by bin: coded, eob 1, every level bin 1, remainder
    // quotient (Rice 0 without neighbours): magnitude 15 + quotient.
    std::vector<uint8_t> bytes;
    RangeEncoder encoder(&bytes);
    BlockContextSet written;
    encoder.encode(written.coded_block[0], 1);
    encoder.encode(written.eob_class[0][0], 0);
    encoder.encode(written.greater_than_one[last_level_context(scan_order(TransformSize::k8x8).scanned[0])], 1);
    encoder.encode(written.greater_than_two[last_level_context(scan_order(TransformSize::k8x8).scanned[0])], 1);
    for (int k = 3; k < kRangeLevel; ++k) encoder.encode(written.level_range[0], 1);
    encode_exp_golomb_bypass(encoder, quotient);
    encoder.encode_bypass(0);
    encoder.finish();
    RangeDecoder decoder(bytes);
    BlockContextSet set;
    BlockLevel out[64];
    int count = 0;
    const bool valid = 15 + quotient <= static_cast<uint32_t>(kMaxLevel);
    ASSERT_EQ(decode_block_levels(decoder, set, 0, out, &count), valid) << quotient;
    if (valid) {
      ASSERT_EQ(count, 1);
      EXPECT_EQ(out[0].level, static_cast<int>(15 + quotient));
    }
  }
}

TEST(CodecBlockCoder, TruncatedAndDamagedBlocksDecodeSafely) {
  std::mt19937 rng(26);
  std::vector<std::array<int16_t, 64>> blocks(60);
  std::vector<uint8_t> bytes;
  {
    RangeEncoder encoder(&bytes);
    BlockContextSet set;
    for (auto& levels : blocks) {
      random_block(rng, levels.data());
      encode_block_levels(encoder, set, levels.data(), 2);
    }
    encoder.finish();
  }
  // Every truncation, and every single-bit flip in the first bytes: each block decodes
  // to bounded levels or is rejected, and the undamaged prefix decodes as written.
  std::vector<std::vector<uint8_t>> damaged;
  for (size_t length = 0; length < bytes.size(); ++length)
    damaged.emplace_back(bytes.begin(), bytes.begin() + length);
  for (size_t bit = 0; bit < std::min<size_t>(bytes.size() * 8, 2000); ++bit) {
    damaged.push_back(bytes);
    damaged.back()[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
  }
  for (const std::vector<uint8_t>& input : damaged) {
    RangeDecoder decoder(input);
    BlockContextSet set;
    for (size_t n = 0; n < blocks.size(); ++n) {
      BlockLevel out[64];
      int count = 0;
      if (!decode_block_levels(decoder, set, 2, out, &count)) break;
      ASSERT_LE(count, 64);
      for (int i = 0; i < count; ++i) {
        ASSERT_LT(out[i].position, 64);
        ASSERT_NE(out[i].level, 0);
        ASSERT_LE(std::abs(out[i].level), kMaxLevel);
        if (i > 0) ASSERT_NE(out[i].position, out[i - 1].position);
      }
    }
  }
  // The truncation one byte short still decodes the first blocks exactly.
  RangeDecoder decoder(std::span<const uint8_t>(bytes.data(), bytes.size() - 1));
  BlockContextSet set;
  EXPECT_EQ(decode_dense(decoder, set, 2), blocks[0]);
}

}  // namespace
}  // namespace svc::codec
