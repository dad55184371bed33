// SPDX-License-Identifier: BSD-2-Clause
// The deblocking filter: its arithmetic on hand-checked edges, the strength map's
// effect, and its use by the frame codecs (signalled, bit-exact, helping where blocky).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "codec/common/bframe_loop_filter.h"
#include "codec/common/intra_frame.h"
#include "codec/common/loop_filter.h"
#include "codec/common/quant.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/intra_encoder.h"

namespace svc::codec {
namespace {

// A padded 3-plane frame of one value per plane, filled by the caller.
struct Frame {
  int width, height;
  std::array<std::vector<uint8_t>, 3> planes;
  Frame(int w, int h) : width(w), height(h) {
    planes[0].assign(static_cast<size_t>(w) * h, 100);
    planes[1].assign(static_cast<size_t>(w / 2) * (h / 2), 128);
    planes[2].assign(planes[1].size(), 128);
  }
  std::array<PlaneView, 3> views() {
    return {PlaneView{planes[0].data(), width, width, height},
            PlaneView{planes[1].data(), width / 2, width / 2, height / 2},
            PlaneView{planes[2].data(), width / 2, width / 2, height / 2}};
  }
  uint8_t& luma(int x, int y) { return planes[0][static_cast<size_t>(y) * width + x]; }
};

TEST(LoopFilter, ThresholdsFollowTheQuantizerIndex) {
  EXPECT_EQ(deblock_qp(0), 0);
  EXPECT_EQ(deblock_qp(128), 22);  // MPEG-2 scale 8: a step of 8, H.265's QP 22
  EXPECT_EQ(deblock_qp(255), 46);
  EXPECT_EQ(deblock_beta(160), 18);   // Q 28
  EXPECT_EQ(deblock_tc(160, 2), 2);   // Q 30
  EXPECT_EQ(deblock_tc(160, 1), 2);   // Q 28
  EXPECT_EQ(deblock_tc(100, 1), 0);   // Q 17: nothing to filter at fine steps
  EXPECT_EQ(deblock_beta(255), 54);   // Q 46
  EXPECT_EQ(deblock_tc(255, 2), 14);  // Q 48
  for (int q = 1; q <= kMaxQIndex; ++q) {
    EXPECT_GE(deblock_beta(q), deblock_beta(q - 1));
    EXPECT_GE(deblock_tc(q, 2), deblock_tc(q, 1));
  }
}

// Flat 100 | flat 106 across x = 8 at qindex 160 (beta 18, tc 2 at strength 2): too big a
// step for the strong filter (|p0 - q0| >= (5 tc + 1) >> 1), so the normal filter with
// both outer samples (section 11.1, worked by hand).
TEST(LoopFilter, NormalFilterOnAHandCheckedEdge) {
  Frame frame(16, 16);
  for (int y = 0; y < 16; ++y) {
    for (int x = 8; x < 16; ++x) frame.luma(x, y) = 106;
  }
  DeblockMap map = DeblockMap::uniform(16, 16, 0);
  for (int uy = 0; uy < 4; ++uy) map.left(2, uy) = 2;
  deblock_frame(map, 160, frame.views());
  const uint8_t expected[8] = {100, 100, 101, 102, 104, 105, 106, 106};
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 8; ++x) EXPECT_EQ(frame.luma(4 + x, y), expected[x]) << x << ", " << y;
  }
}

TEST(LoopFilter, StrongFilterSmoothsASmallStepBetweenFlatBlocks) {
  Frame frame(16, 16);
  for (int y = 8; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) frame.luma(x, y) = 103;
  }
  DeblockMap map = DeblockMap::uniform(16, 16, 2);
  deblock_frame(map, 200, frame.views());  // beta 34, tc 5: strong
  // p2..q2 = (2*100 + 3*100 + 100 + 100 + 103 + 4) >> 3 = 100, (100*3 + 103 + 2) >> 2 = 101, ...
  const uint8_t expected[8] = {100, 100, 101, 101, 102, 102, 103, 103};
  for (int x = 0; x < 16; ++x) {
    for (int y = 0; y < 8; ++y) EXPECT_EQ(frame.luma(x, 4 + y), expected[y]) << x << ", " << y;
  }
}

TEST(LoopFilter, StrengthZeroAndTexturedEdgesStay) {
  Frame frame(32, 16);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 32; ++x) frame.luma(x, y) = x < 8 ? 100 : (x < 16 ? 106 : (x % 2 ? 200 : 40));
  }
  const auto before = frame.planes;
  DeblockMap map = DeblockMap::uniform(32, 16, 0);
  deblock_frame(map, 255, frame.views());
  EXPECT_EQ(frame.planes, before);                     // strength 0 everywhere
  for (int uy = 0; uy < 4; ++uy) map.left(6, uy) = 2;  // only the edge inside the stripes
  deblock_frame(map, 255, frame.views());
  EXPECT_EQ(frame.planes, before);  // textured sides: dp + dq >= beta, the step is content
}

// A smooth image at a coarse index: blocky without the filter, closer to the source with
// it; the encoder signals it, and the decoder and the semi-decoded path agree.
TEST(LoopFilter, IntraFramesSignalAndApplyDeblocking) {
  ImageYCbCr420 source;
  source.width = 96;
  source.height = 64;
  source.y.resize(96 * 64);
  source.cb.assign(48 * 32, 120);
  source.cr.assign(48 * 32, 136);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 96; ++x) {
      source.y[static_cast<size_t>(y) * 96 + x] = static_cast<uint8_t>(60 + x + y / 2 + 8 * std::sin(x * 0.05));
    }
  }
  auto error = [&](const ImageYCbCr420& image) {
    double sum = 0;
    for (size_t i = 0; i < image.y.size(); ++i) sum += std::pow(image.y[i] - source.y[i], 2.0);
    return sum;
  };
  const CodingParams on{.qindex = 200, .deblocking = true, .cdef = false};  // CDEF aside (codec_cdef_test.cc)
  const CodingParams off{.qindex = 200, .deblocking = false, .cdef = false};
  ImageYCbCr420 filtered, plain, decoded, from_coefficients;
  const std::vector<uint8_t> with = encode_intra_frame(source, on, &filtered);
  const std::vector<uint8_t> without = encode_intra_frame(source, off, &plain);
  ASSERT_EQ(with[kIntraFlagsByte] & kLoopFilterKnownBits, kLoopFilterDeblocking);
  ASSERT_EQ(without[kIntraFlagsByte] & kLoopFilterKnownBits, 0);
  EXPECT_TRUE(std::equal(with.begin() + 4, with.end(), without.begin() + 4, without.end()));  // same symbols
  EXPECT_LT(error(filtered), error(plain));
  ASSERT_TRUE(decode_intra_frame(with, 96, 64, &decoded).ok());
  EXPECT_EQ(decoded.y, filtered.y);
  EXPECT_EQ(decoded.cb, filtered.cb);
  EXPECT_EQ(decoded.cr, filtered.cr);
  CoefficientFrame coefficients;
  ASSERT_TRUE(parse_intra_frame(with, 96, 64, &coefficients).ok());
  EXPECT_EQ(coefficients.loop_filters, kLoopFilterDeblocking);
  reconstruct_intra_frame(coefficients, &from_coefficients);
  EXPECT_EQ(from_coefficients.y, filtered.y);
}

// B-face strengths: 2 at an intra macroblock, 1 at coded blocks or differing motion,
// 0 inside an uncoded inter macroblock and between macroblocks with the same motion.
TEST(LoopFilter, BFrameStrengthsFollowTheCoding) {
  ImageYCbCr420 reference;
  reference.width = 48;
  reference.height = 16;
  reference.y.assign(48 * 16, 0);
  reference.cb.assign(24 * 8, 0);
  reference.cr.assign(24 * 8, 0);
  bframe::FrameState s;
  bframe::init_state(s, 48, 16, 128, &reference, nullptr);
  for (auto& mb : s.macroblocks) {
    mb.mode = MacroblockMode::kForward;
    mb.inter_mode = MacroblockMode::kForward;
  }
  s.macroblocks[2].mode = MacroblockMode::kIntra;
  s.coded[0][1] = 1;  // luma block (1, 0): second block of the first macroblock
  DeblockMap map = bframe::deblock_map(s);
  EXPECT_EQ(map.left(2, 0), 1);  // x = 8: block (1, 0) is coded
  EXPECT_EQ(map.left(2, 2), 0);  // x = 8, lower blocks: same macroblock, nothing coded
  EXPECT_EQ(map.left(4, 2), 0);  // x = 16: same vector (0, 0)
  EXPECT_EQ(map.left(8, 0), 2);  // x = 32: the intra macroblock
  EXPECT_EQ(map.top(5, 2), 0);   // y = 8 inside macroblock 1
  s.macroblocks[1].vectors[0] = MotionVector{4, 0};
  EXPECT_EQ(bframe::deblock_map(s).left(4, 2), 1);  // a whole pixel apart (quarter-pel vectors)
  s.macroblocks[1].vectors[0] = MotionVector{2, -3};
  EXPECT_EQ(bframe::deblock_map(s).left(4, 2), 0);  // half a pixel: no step to hide
}

}  // namespace
}  // namespace svc::codec
