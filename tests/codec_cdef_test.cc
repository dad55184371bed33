// SPDX-License-Identifier: BSD-2-Clause
// CDEF: the direction search on hand-made lines, the filter on a hand-checked block, its
// syntax, and its use by the frame codecs (signalled, bit-exact, robust to damage).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/cdef.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/cdef_syntax.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/decoder/range_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/cdef_search.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/range_encoder.h"
#include "support/reference_hints.h"

namespace svc::codec {
namespace {

// The plain references and this machine's table.
std::array<dsp::DspTable, 2> tables() { return {dsp::make_dsp_table(0), dsp::get_dsp()}; }

TEST(Cdef, DirectionOfHandMadeLines) {
  uint8_t rows[64], columns[64], diagonal[64], anti_diagonal[64];
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      rows[8 * i + j] = static_cast<uint8_t>(40 + 20 * i);  // constant along each row
      columns[8 * i + j] = static_cast<uint8_t>(40 + 20 * j);
      diagonal[8 * i + j] = static_cast<uint8_t>(((i + j) % 2) * 100 + 50);     // constant on i + j
      anti_diagonal[8 * i + j] = static_cast<uint8_t>(((i - j + 8) % 3) * 60);  // constant on i - j
    }
  }
  for (const dsp::DspTable& table : tables()) {
    int32_t variance = 0;
    EXPECT_EQ(table.cdef_direction_8x8(rows, 8, &variance), 2);  // horizontal lines
    EXPECT_GT(variance, 0);
    EXPECT_EQ(table.cdef_direction_8x8(columns, 8, &variance), 6);   // vertical lines
    EXPECT_EQ(table.cdef_direction_8x8(diagonal, 8, &variance), 0);  // up and to the right
    EXPECT_EQ(table.cdef_direction_8x8(anti_diagonal, 8, &variance), 4);
    uint8_t flat[64];
    std::fill(std::begin(flat), std::end(flat), 90);
    EXPECT_EQ(table.cdef_direction_8x8(flat, 8, &variance), 0);
    EXPECT_EQ(variance, 0);  // nothing to follow: the primary filter is off
  }
}

// A spike of 3 on a flat block, secondary strength 4, damping 3: each of the 12 secondary
// taps constrains -3 to -3 (shift 1: 4 - (3 >> 1) = 3), sum -3 (4 x 2 + 4 x 1) = -36,
// (8 - 36 - 1) >> 4 = -2: 103 becomes 101; the flat neighbours gain at most (8 + 6) >> 4 = 0.
TEST(Cdef, FilterOfAHandCheckedSpike) {
  for (const dsp::DspTable& table : tables()) {
    std::array<uint16_t, 12 * 12> block;
    block.fill(100);
    block[6 * 12 + 6] = 103;  // sample (4, 4) of the block
    std::array<uint8_t, 64> out{};
    table.cdef_filter_block(block.data() + 2 * 12 + 2, 12, out.data(), 8, 8, dsp::CdefTaps{0, 4, 0, 3});
    for (int i = 0; i < 64; ++i) EXPECT_EQ(out[i], i == 4 * 8 + 4 ? 101 : 100) << "sample " << i;
  }
}

TEST(Cdef, UnavailableSamplesTakeNoPart) {
  for (const dsp::DspTable& table : tables()) {
    std::array<uint16_t, 12 * 12> block;
    block.fill(dsp::kCdefUnavailable);
    for (int y = 2; y < 10; ++y) {
      for (int x = 2; x < 10; ++x) block[y * 12 + x] = static_cast<uint16_t>(100 + ((x + y) & 1) * 2);
    }
    std::array<uint8_t, 64> out{};
    table.cdef_filter_block(block.data() + 2 * 12 + 2, 12, out.data(), 8, 8, dsp::CdefTaps{6, 2, 3, 4});
    for (uint8_t v : out) {
      EXPECT_GE(v, 100);
      EXPECT_LE(v, 102);  // the filter never leaves the range of the samples it read
    }
  }
}

TEST(Cdef, SyntaxRoundTrips) {
  CdefParams params{{{3, 1}, {0, 2}, {15, 3}}, {0, 1, 2, 3, 3, 0, 1, 1, 2}};
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  write_cdef_syntax(encoder, params, 3, 3);
  encoder.finish();
  RangeDecoder decoder(bytes);
  CdefParams read;
  read_cdef_syntax(decoder, 3, 3, &read);
  EXPECT_LE(decoder.overrun(), kImplicitZeroBytes);  // the final zeros left out
  ASSERT_EQ(read.presets.size(), 3u);
  EXPECT_EQ(read.presets[2].primary, 15);
  EXPECT_EQ(read.presets[2].secondary_code, 3);
  EXPECT_EQ(read.presets[1].secondary_code, 2);
  EXPECT_EQ(read.unit_presets, params.unit_presets);
}

// Sharp-edged shapes with noise: coarse quantization rings around them.
ImageYCbCr420 ringing_source(int width, int height, int shift) {
  ImageYCbCr420 source;
  source.width = width;
  source.height = height;
  source.y.resize(static_cast<size_t>(width) * height);
  source.cb.resize(static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2));
  source.cr.resize(source.cb.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int u = x + shift;
      const bool inside = ((u / 11 + y / 13) % 3 == 0) || (u + 2 * y) % 37 < 6;
      source.y[static_cast<size_t>(y) * width + x] =
          static_cast<uint8_t>((inside ? 200 : 50) + (u * 7 + y * 3) % 5);
    }
  }
  for (size_t i = 0; i < source.cb.size(); ++i) {
    source.cb[i] = static_cast<uint8_t>(110 + (i % 7));
    source.cr[i] = static_cast<uint8_t>(140 - (i % 5));
  }
  return source;
}

double luma_error(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  double sum = 0;
  for (size_t i = 0; i < a.y.size(); ++i) sum += std::pow(a.y[i] - b.y[i], 2.0);
  return sum;
}

TEST(Cdef, IntraFramesSignalChooseAndDecodeExactly) {
  const ImageYCbCr420 source = ringing_source(136, 72, 0);
  CodingParams on, off;
  on.qindex = off.qindex = 170;
  off.cdef = false;
  ImageYCbCr420 filtered, plain, decoded, from_coefficients;
  const std::vector<uint8_t> with = encode_intra_frame(source, on, &filtered);
  const std::vector<uint8_t> without = encode_intra_frame(source, off, &plain);
  ASSERT_NE(with[kIntraFlagsByte] & kLoopFilterCdef, 0);
  EXPECT_EQ(without[kIntraFlagsByte] & kLoopFilterCdef, 0);
  EXPECT_LT(luma_error(filtered, source), luma_error(plain, source));
  ASSERT_TRUE(decode_intra_frame(with, 136, 72, &decoded).ok());
  EXPECT_EQ(decoded.y, filtered.y);
  EXPECT_EQ(decoded.cb, filtered.cb);
  EXPECT_EQ(decoded.cr, filtered.cr);
  CoefficientFrame coefficients;
  ASSERT_TRUE(parse_intra_frame(with, 136, 72, &coefficients).ok());
  EXPECT_FALSE(coefficients.cdef.presets.empty());
  reconstruct_intra_frame(coefficients, &from_coefficients);
  EXPECT_EQ(from_coefficients.y, filtered.y);
  EXPECT_EQ(from_coefficients.cr, filtered.cr);
}

// The half search (encoder speed 5) picks its presets among every other candidate
// strength only, and its frames decode to the encoder's reconstruction as any other.
TEST(Cdef, HalfSearchKeepsToEveryOtherCandidateAndDecodesExactly) {
  const ImageYCbCr420 source = ringing_source(136, 72, 0);
  const std::vector<std::pair<int, int>> allowed = {{0, 1}, {1, 0}, {1, 1}, {3, 1}, {4, 1}, {6, 2}, {10, 3}};
  for (int qindex : {120, 170, 220}) {
    CodingParams half;
    half.qindex = qindex;
    half.full_cdef_search = false;
    ImageYCbCr420 filtered, decoded;
    const std::vector<uint8_t> bytes = encode_intra_frame(source, half, &filtered);
    ASSERT_TRUE(decode_intra_frame(bytes, 136, 72, &decoded).ok());
    EXPECT_EQ(decoded.y, filtered.y) << qindex;
    EXPECT_EQ(decoded.cb, filtered.cb) << qindex;
    CoefficientFrame coefficients;
    ASSERT_TRUE(parse_intra_frame(bytes, 136, 72, &coefficients).ok());
    if (qindex == 170) EXPECT_FALSE(coefficients.cdef.presets.empty());
    for (const CdefStrength& preset : coefficients.cdef.presets) {
      const std::pair<int, int> strength{preset.primary, preset.secondary_code};
      EXPECT_NE(std::find(allowed.begin(), allowed.end(), strength), allowed.end())
          << qindex << ": " << strength.first << "," << strength.second;
    }
  }
}

TEST(Cdef, DamagedSyntaxIsRejectedOrDecodes) {
  const ImageYCbCr420 source = ringing_source(136, 72, 0);
  CodingParams params;
  params.qindex = 170;
  const std::vector<uint8_t> bytes = encode_intra_frame(source, params, nullptr);
  ASSERT_NE(bytes[kIntraFlagsByte] & kLoopFilterCdef, 0);
  ImageYCbCr420 decoded;
  // The CDEF syntax is last: without the final bytes the decoder runs out.
  const Status truncated =
      decode_intra_frame(std::span<const uint8_t>(bytes.data(), bytes.size() - kImplicitZeroBytes - 1), 136, 72,
                         &decoded);
  EXPECT_EQ(truncated.code(), ErrorCode::kCorruptData);
  // Flipping the flag off leaves the CDEF syntax as trailing bytes, or (when it fits in
  // the decoder's lookahead) decodes the frame unfiltered: never the filtered pixels.
  ImageYCbCr420 filtered;
  ASSERT_TRUE(decode_intra_frame(bytes, 136, 72, &filtered).ok());
  std::vector<uint8_t> flipped = bytes;
  flipped[kIntraFlagsByte] ^= kLoopFilterCdef;
  const Status unfiltered = decode_intra_frame(flipped, 136, 72, &decoded);
  EXPECT_TRUE(!unfiltered.ok() || decoded.y != filtered.y);
  // Damage in the last bytes: an error or a whole frame, never a crash.
  for (size_t i = bytes.size() - std::min<size_t>(bytes.size() - 4, 12); i < bytes.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> damaged = bytes;
      damaged[i] ^= static_cast<uint8_t>(1 << bit);
      if (decode_intra_frame(damaged, 136, 72, &decoded).ok()) {
        EXPECT_EQ(decoded.y.size(), 136u * 72u);
        EXPECT_EQ(decoded.cb.size(), 68u * 36u);
      }
    }
  }
}

TEST(Cdef, BFramesDecodeToTheEncodersReconstruction) {
  CodingParams intra;
  intra.qindex = 150;
  ImageYCbCr420 reference;
  encode_intra_frame(ringing_source(136, 72, 0), intra, &reference);
  const ImageYCbCr420 source = ringing_source(136, 72, 2);
  BFrameParams params;
  params.qindex = 200;
  ImageYCbCr420 reconstruction, decoded;
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, reference, nullptr, candidate_hints({}, {}), params, &reconstruction, nullptr);
  ASSERT_FALSE(bytes.empty());
  ASSERT_TRUE(decode_b_frame(bytes, 136, 72, reference, nullptr, &decoded).ok());
  EXPECT_EQ(decoded.y, reconstruction.y);
  EXPECT_EQ(decoded.cb, reconstruction.cb);
  EXPECT_EQ(decoded.cr, reconstruction.cr);
  params.cdef = false;
  const std::vector<uint8_t> without =
      encode_b_frame(source, reference, nullptr, candidate_hints({}, {}), params, nullptr, nullptr);
  EXPECT_EQ(without[kIntraFlagsByte] & kLoopFilterCdef, 0);
}

}  // namespace
}  // namespace svc::codec
