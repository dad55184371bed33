// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <vector>

#include "codec/common/context_priors.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/intra_encoder.h"

namespace svc::codec {
namespace {

TEST(ContextPriors, TablesListEveryContextOfTheirBundle) {
  EXPECT_EQ(context_count(ContextBundle::kIntraFrame), 1056);
  EXPECT_EQ(context_count(ContextBundle::kBFrame), 1817);
  for (ContextBundle bundle : {ContextBundle::kIntraFrame, ContextBundle::kBFrame}) {
    const auto priors = context_priors(bundle);
    ASSERT_EQ(static_cast<int>(priors.size()), context_count(bundle));
    EXPECT_TRUE(std::all_of(priors.begin(), priors.end(), [](uint16_t p) { return p >= 512 && p <= 32256; }));
    // Trained: many contexts have settled away from 1/2. Not all: every block context set
    // holds the contexts of every transform size, and chroma blocks (8x8) and B-face
    // residuals (4x4, 8x8, 16x16) never use the rectangular sizes' ones.
    const auto trained = std::count_if(priors.begin(), priors.end(), [](uint16_t p) { return p != 16384; });
    EXPECT_GT(trained, static_cast<long>(priors.size()) * 2 / 5);
  }
}

TEST(ContextPriors, IntraFrameContextsStartAtTheTableInItsOrder) {
  intra::PlaneContexts luma, chroma;
  prime_intra_frame_contexts(luma, chroma);
  const auto priors = context_priors(ContextBundle::kIntraFrame);
  EXPECT_EQ(luma.modes.is_most_probable[0][0].fast, priors[0]);
  EXPECT_EQ(luma.modes.is_most_probable[0][0].slow, priors[0]);
  EXPECT_EQ(luma.modes.is_most_probable[0][0].seen, 0);  // adapts as fast as a fresh context
  EXPECT_EQ(luma.residual.coded_block[0].fast, priors[85]);
  EXPECT_EQ(chroma.modes.is_most_probable[0][0].fast, priors[528]);
  EXPECT_EQ(chroma.types.bits[8][4][2].fast, priors.back());
  // Priming leaves the header-driven switch alone.
  EXPECT_FALSE(luma.types.enabled);
}

TEST(ContextPriors, BFrameContextsStartAtTheTableInItsOrder) {
  bframe::SyntaxContexts contexts;
  prime_bframe_contexts(contexts);
  const auto priors = context_priors(ContextBundle::kBFrame);
  EXPECT_EQ(contexts.skip[0].fast, priors[0]);
  EXPECT_EQ(contexts.intra[0].fast, priors[3]);
  EXPECT_EQ(contexts.mvd_magnitude[0].above[0].fast, priors[18]);
  EXPECT_EQ(contexts.warp[0].fast, priors[86]);
  EXPECT_EQ(contexts.intra_luma.modes.is_most_probable[0][0].fast, priors[243]);
  // Then luma_16x16[3], luma_4x4, predictor_index[2] and skip_predictor_index[2].
  EXPECT_EQ(contexts.inter_chroma.level_range[20].fast, priors[priors.size() - 9]);
  EXPECT_EQ(contexts.skip_predictor_index[1].fast, priors.back());
  EXPECT_EQ(contexts.skip_predictor_index[1].seen, 0);
}

std::atomic<int> observed_frames{0};
std::atomic<int> observed_settled{0};

void count_frame(ContextBundle bundle, std::span<const uint16_t> probabilities, std::span<const uint8_t> seen) {
  if (bundle != ContextBundle::kIntraFrame || static_cast<int>(probabilities.size()) != 1056 ||
      seen.size() != probabilities.size()) {
    return;
  }
  ++observed_frames;
  observed_settled += static_cast<int>(std::count(seen.begin(), seen.end(), AdaptiveBit::kSettled));
}

TEST(ContextPriors, ObserverSeesEachEncodedFramesUnprimedContextsUntilRemoved) {
  ImageYCbCr420 image;
  image.width = image.height = 64;
  image.y.resize(64 * 64);
  for (size_t i = 0; i < image.y.size(); ++i) image.y[i] = static_cast<uint8_t>((i * 37 + (i >> 6) * 11) & 255);
  image.cb.assign(32 * 32, 100);
  image.cr.assign(32 * 32, 150);
  CodingParams params;
  params.qindex = 60;
  const auto primed = encode_intra_frame(image, params, nullptr);
  set_context_observer(count_frame);
  const auto training = encode_intra_frame(image, params, nullptr);
  intra::PlaneContexts luma, chroma;
  prime_intra_frame_contexts(luma, chroma);  // while training: left at 1/2
  set_context_observer(nullptr);
  EXPECT_EQ(luma.residual.coded_block[0].fast, 16384);
  EXPECT_EQ(encode_intra_frame(image, params, nullptr), primed);
  EXPECT_NE(training, primed);  // trained probabilities change the bytes
  EXPECT_EQ(observed_frames.load(), 1);
  EXPECT_GT(observed_settled.load(), 0);  // a textured 64x64 frame settles some contexts
}

}  // namespace
}  // namespace svc::codec
