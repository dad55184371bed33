// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/intra_frame.h"
#include "codec/common/motion_compensation.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/log_search.h"
#include "support/damaged_payload.h"
#include "support/reference_hints.h"

namespace svc::codec {
namespace {

// Smooth random texture at several scales (see codec_motion_test.cc), deterministic.
std::vector<uint8_t> texture_plane(int width, int height, int cell, uint32_t seed) {
  std::mt19937 rng(seed);
  const int gw = width / cell + 2, gh = height / cell + 2;
  std::vector<double> grid(static_cast<size_t>(gw) * gh);
  for (double& v : grid) v = 30 + static_cast<double>(rng() % 196);
  std::vector<uint8_t> plane(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double gx = static_cast<double>(x) / cell, gy = static_cast<double>(y) / cell;
      const int ix = static_cast<int>(gx), iy = static_cast<int>(gy);
      const double fx = gx - ix, fy = gy - iy;
      auto g = [&](int u, int v) { return grid[static_cast<size_t>(v) * gw + u]; };
      double value = (1 - fy) * ((1 - fx) * g(ix, iy) + fx * g(ix + 1, iy)) +
                     fy * ((1 - fx) * g(ix, iy + 1) + fx * g(ix + 1, iy + 1));
      value += 12 * std::sin(x * 0.45 + y * 0.2) + static_cast<double>(rng() % 5) - 2;
      plane[static_cast<size_t>(y) * width + x] = static_cast<uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  }
  return plane;
}

// image(x, y) = texture(x + ox, y + oy) for a fixed texture per seed.
ImageYCbCr420 textured_crop(int width, int height, int ox, int oy, uint32_t seed = 7) {
  const int tw = 320, th = 320;
  const std::vector<uint8_t> luma = texture_plane(tw, th, 9, seed);
  const std::vector<uint8_t> chroma = texture_plane(tw, th, 21, seed + 1);
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.resize(static_cast<size_t>(cw) * ch);
  image.cr.resize(image.cb.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x)
      image.y[static_cast<size_t>(y) * width + x] = luma[static_cast<size_t>(y + oy) * tw + x + ox];
  }
  // Chroma sampled at even pixels so an even shift moves it by whole chroma samples.
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      const size_t t = static_cast<size_t>(2 * y + oy) * tw + 2 * x + ox;
      image.cb[static_cast<size_t>(y) * cw + x] = chroma[t];
      image.cr[static_cast<size_t>(y) * cw + x] = static_cast<uint8_t>(255 - chroma[t] / 2);
    }
  }
  return image;
}

double psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double squared = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    squared += d * d;
  }
  if (squared == 0) return 99.0;
  return 10 * std::log10(255.0 * 255.0 * static_cast<double>(a.size()) / squared);
}

void expect_same_image(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  EXPECT_TRUE(a.y == b.y);
  EXPECT_TRUE(a.cb == b.cb);
  EXPECT_TRUE(a.cr == b.cr);
}

// The same candidate list for every macroblock.
FaceCandidates uniform_candidates(int width, int height, const CandidateList& list) {
  return FaceCandidates(static_cast<size_t>((width + 15) / 16) * ((height + 15) / 16), list);
}

// An intra-coded reference as the decoder would hold it.
ImageYCbCr420 decoded_intra(const ImageYCbCr420& image, int qindex) {
  ImageYCbCr420 reconstruction;
  encode_intra_frame(image, CodingParams{qindex}, &reconstruction);
  return reconstruction;
}

// Decodes every prefix of `valid` with `decodes` (true when it decoded) and returns how
// many cuts by more than the final zeros a payload may leave out decoded all the same:
// those whose symbols, decoded from zeros in place of the missing bytes, happen to need
// no more bytes (docs/codec.md 6.1).
template <class Decodes>
int undetected_truncations(const std::vector<uint8_t>& valid, Decodes decodes) {
  int undetected = 0;
  for (size_t length = 0; length < valid.size(); ++length) {
    const std::vector<uint8_t> cut(valid.begin(), valid.begin() + static_cast<ptrdiff_t>(length));
    undetected += decodes(cut) && valid.size() - length > kImplicitZeroBytes;
  }
  return undetected;
}

TEST(BFrame, KnownMotionPredictsNearlyPerfectlyAndCodesSmall) {
  const int w = 128, h = 96, q = 128;
  // source(x, y) = reference(x + 3, y + 2): vector (+12, +8) quarter-pels.
  const ImageYCbCr420 reference = decoded_intra(textured_crop(w, h, 40, 40), q);
  const ImageYCbCr420 source = textured_crop(w, h, 43, 42);
  const FaceCandidates candidates =
      uniform_candidates(w, h,
                         {MotionVector{0, 0}, MotionVector{12, 8}, MotionVector{-16, 4}, MotionVector{10, 8}});
  BFrameParams params;
  params.qindex = q;
  ImageYCbCr420 reconstruction;
  BFrameStats stats;
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, reference, nullptr, candidate_hints(candidates, {}), params, &reconstruction, &stats);
  ImageYCbCr420 intra_reconstruction;
  const std::vector<uint8_t> intra = encode_intra_frame(source, CodingParams{q}, &intra_reconstruction);
  ASSERT_FALSE(bytes.empty());
  EXPECT_LT(bytes.size() * 4, intra.size()) << bytes.size() << " vs intra " << intra.size();
  EXPECT_EQ(stats.macroblocks, 48);
  EXPECT_EQ(stats.mb_intra + stats.mb_forward + stats.mb_backward + stats.mb_bidirectional + stats.mb_skipped, 48);
  EXPECT_EQ(stats.mb_backward + stats.mb_bidirectional, 0);  // one reference
  EXPECT_GE(stats.mb_skipped + stats.mb_forward, 44);
  EXPECT_EQ(stats.candidates_evaluated, 48 * 4);
  EXPECT_GT(psnr(source.y, reconstruction.y), psnr(source.y, intra_reconstruction.y) - 0.5);

  // At the suggested B qindex most macroblocks need no residual at all.
  params.qindex = suggested_b_qindex(q);
  BFrameStats coarser_stats;
  ImageYCbCr420 coarser;
  const std::vector<uint8_t> coarser_bytes =
      encode_b_frame(source, reference, nullptr, candidate_hints(candidates, {}), params, &coarser, &coarser_stats);
  EXPECT_LT(coarser_bytes.size() * 7, intra.size()) << coarser_bytes.size() << " vs intra " << intra.size();
  EXPECT_GE(coarser_stats.mb_skipped, 24);
  // Within 2 dB of intra coding at the 2.5x finer step: the prediction carries the
  // detail (lambda 0.25 trades some PSNR for bytes; 0.12 gave 1.0 dB; the I-face's
  // rate-distortion quantization, which starts from nearest rounding, added 0.15 dB).
  EXPECT_GT(psnr(source.y, coarser.y), psnr(source.y, intra_reconstruction.y) - 2.0);

  ImageYCbCr420 decoded;
  std::vector<MacroblockMode> modes;
  ASSERT_TRUE(decode_b_frame(bytes, w, h, reference, nullptr, &decoded, &modes).ok());
  expect_same_image(decoded, reconstruction);
  EXPECT_EQ(modes, stats.modes);
}

TEST(BFrame, ScreenedPredictionErrorSeparatesWhatTheReferenceSees) {
  const int w = 128, h = 64, q = 128;
  const ImageYCbCr420 source = textured_crop(w, h, 20, 20);
  const ImageYCbCr420 other = textured_crop(w, h, 20, 20, 1234);
  // The reference shows the source's left half; its right half is another texture.
  ImageYCbCr420 reference = source;
  for (int y = 0; y < h; ++y) {
    for (int x = w / 2; x < w; ++x)
      reference.y[static_cast<size_t>(y) * w + x] = other.y[static_cast<size_t>(y) * w + x];
  }
  reference = decoded_intra(reference, q);
  const FaceCandidates zero = uniform_candidates(w, h, {MotionVector{0, 0}});
  BFrameParams params;
  params.qindex = q;
  BFrameStats stats;
  ASSERT_FALSE(
      encode_b_frame(source, reference, nullptr, candidate_hints(zero, {}), params, nullptr, &stats).empty());
  EXPECT_EQ(stats.screened_prediction_pixels[0] + stats.screened_prediction_pixels[1], w * h);
  EXPECT_EQ(stats.screened_prediction_pixels[0], 256 * stats.mb_intra);
  ASSERT_GT(stats.mb_intra, 0);
  ASSERT_LT(stats.mb_intra, stats.macroblocks);
  auto mean_error = [&](size_t k) {
    return static_cast<double>(stats.screened_prediction_sse[k]) /
           static_cast<double>(stats.screened_prediction_pixels[k]);
  };
  // Where intra won the reference showed another texture: its error is far larger.
  EXPECT_GT(mean_error(0), 10 * mean_error(1)) << mean_error(0) << " vs " << mean_error(1);
}

TEST(BFrame, TwoReferencesPickTheOneWhereTheContentIsVisible) {
  const int w = 128, h = 64, q = 128;
  const ImageYCbCr420 source = textured_crop(w, h, 20, 20);
  const ImageYCbCr420 other = textured_crop(w, h, 20, 20, 1234);
  // Reference 0 shows the source's left half, reference 1 its right half; the rest of
  // each is another texture (as if occluded).
  ImageYCbCr420 ref0 = source, ref1 = source;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      (x < w / 2 ? ref1 : ref0).y[i] = other.y[i];
    }
  }
  for (int y = 0; y < h / 2; ++y) {
    for (int x = 0; x < w / 2; ++x) {
      const size_t i = static_cast<size_t>(y) * (w / 2) + x;
      ImageYCbCr420& hidden = x < w / 4 ? ref1 : ref0;
      hidden.cb[i] = other.cb[i];
      hidden.cr[i] = other.cr[i];
    }
  }
  ref0 = decoded_intra(ref0, q);
  ref1 = decoded_intra(ref1, q);
  const FaceCandidates zero = uniform_candidates(w, h, {MotionVector{0, 0}});
  BFrameParams params;
  params.qindex = q;
  ImageYCbCr420 reconstruction;
  BFrameStats stats;
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, ref0, &ref1, candidate_hints(zero, zero), params, &reconstruction, &stats);
  ASSERT_FALSE(bytes.empty());
  const int mbs_x = w / 16;
  int forward_left = 0, backward_right = 0;
  for (int my = 0; my < h / 16; ++my) {
    for (int mx = 0; mx < mbs_x; ++mx) {
      const MacroblockMode mode = stats.modes[static_cast<size_t>(my) * mbs_x + mx];
      const bool left = mx < mbs_x / 2;
      EXPECT_NE(mode, left ? MacroblockMode::kBackward : MacroblockMode::kForward) << mx << ", " << my;
      EXPECT_NE(mode, MacroblockMode::kBidirectional) << mx << ", " << my;
      EXPECT_NE(mode, MacroblockMode::kIntra) << mx << ", " << my;
      forward_left += left && mode == MacroblockMode::kForward;
      backward_right += !left && mode == MacroblockMode::kBackward;
    }
  }
  EXPECT_GE(forward_left, 1);
  EXPECT_GE(backward_right, 1);
  EXPECT_GT(psnr(source.y, reconstruction.y), 36.0);
  ImageYCbCr420 intra_reconstruction;
  const std::vector<uint8_t> intra = encode_intra_frame(source, CodingParams{q}, &intra_reconstruction);
  EXPECT_LT(bytes.size() * 4, intra.size()) << bytes.size() << " vs intra " << intra.size();

  ImageYCbCr420 decoded;
  std::vector<MacroblockMode> modes;
  ASSERT_TRUE(decode_b_frame(bytes, w, h, ref0, &ref1, &decoded, &modes).ok());
  expect_same_image(decoded, reconstruction);
  EXPECT_EQ(modes, stats.modes);
}

TEST(BFrame, WrongCandidatesFallBackToIntra) {
  const int w = 96, h = 64, q = 128;
  const ImageYCbCr420 source = textured_crop(w, h, 0, 0);
  const ImageYCbCr420 unrelated = decoded_intra(textured_crop(w, h, 0, 0, 555), q);
  BFrameParams params;
  params.qindex = q;
  ImageYCbCr420 reconstruction, intra_reconstruction;
  BFrameStats stats;
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, unrelated, nullptr,
                     candidate_hints(uniform_candidates(w, h, {MotionVector{0, 0}, MotionVector{6, 4}}), {}),
                     params, &reconstruction, &stats);
  const std::vector<uint8_t> intra = encode_intra_frame(source, CodingParams{q}, &intra_reconstruction);
  EXPECT_GE(stats.mb_intra, 20) << "of " << stats.macroblocks;
  // Intra macroblocks are coded as an I-face codes its blocks, at the same qindex but
  // with the B-face's lambda and the intra flag's bits on top.
  EXPECT_GT(psnr(source.y, reconstruction.y), psnr(source.y, intra_reconstruction.y) - 2.0);
  EXPECT_LT(bytes.size(), intra.size() * 6 / 5) << bytes.size() << " vs intra " << intra.size();
  ImageYCbCr420 decoded;
  ASSERT_TRUE(decode_b_frame(bytes, w, h, unrelated, nullptr, &decoded).ok());
  expect_same_image(decoded, reconstruction);
}

// A cheap skip ends a macroblock's search (BFrameParams::skip_exit_bits): where the
// reference shows the source the macroblocks are skipped without a motion search, where
// it shows another texture they are searched and coded as before; every setting decodes
// exactly, and a threshold no skip can miss skips every macroblock without a search.
TEST(BFrame, EarlySkipEndsTheSearchOnlyWhereSkipIsCheap) {
  const int w = 128, h = 64, q = 128;
  const ImageYCbCr420 source = decoded_intra(textured_crop(w, h, 20, 20), q - 40);
  const ImageYCbCr420 other = textured_crop(w, h, 20, 20, 1234);
  ImageYCbCr420 reference = source;
  for (int y = 0; y < h; ++y) {
    for (int x = w / 2; x < w; ++x)
      reference.y[static_cast<size_t>(y) * w + x] = other.y[static_cast<size_t>(y) * w + x];
  }
  const FaceCandidates zero = uniform_candidates(w, h, {MotionVector{0, 0}, MotionVector{4, 0}});
  struct Run {
    BFrameStats stats;
    std::vector<uint8_t> bytes;
  };
  auto encode = [&](double skip_exit_bits) {
    BFrameParams params;
    params.qindex = q;
    params.skip_exit_bits = skip_exit_bits;
    Run run;
    ImageYCbCr420 reconstruction, decoded;
    run.bytes =
        encode_b_frame(source, reference, nullptr, candidate_hints(zero, {}), params, &reconstruction, &run.stats);
    std::vector<MacroblockMode> modes;
    EXPECT_TRUE(decode_b_frame(run.bytes, w, h, reference, nullptr, &decoded, &modes).ok()) << skip_exit_bits;
    expect_same_image(decoded, reconstruction);
    EXPECT_EQ(modes, run.stats.modes) << skip_exit_bits;
    EXPECT_EQ(run.stats.screened_prediction_pixels[0] + run.stats.screened_prediction_pixels[1], w * h);
    return run;
  };
  const Run full = encode(0), early = encode(kEarlySkipBits), all = encode(1e12);
  const int mbs_x = w / 16;
  for (size_t m = 0; m < early.stats.modes.size(); ++m) {
    if (static_cast<int>(m) % mbs_x < mbs_x / 2) {
      EXPECT_EQ(early.stats.modes[m], MacroblockMode::kSkipped) << m;
      EXPECT_EQ(full.stats.modes[m], MacroblockMode::kSkipped) << m;
    }
  }
  EXPECT_GT(early.stats.mb_intra, 0);
  EXPECT_GT(early.stats.sad_evaluations, 0);
  // The left half's macroblocks searched no vector: at least one SAD each fewer.
  EXPECT_GE(full.stats.sad_evaluations - early.stats.sad_evaluations, w / 32 * h / 16);
  EXPECT_EQ(all.stats.mb_skipped, all.stats.macroblocks);
  EXPECT_EQ(all.stats.sad_evaluations, 0);
  EXPECT_LT(all.bytes.size(), early.bytes.size());

  // Where the reference shows the whole face, no macroblock searches and the choices
  // (every one a skip) and bytes are the full search's.
  reference = source;
  const Run same_full = encode(0), same_early = encode(kEarlySkipBits);
  EXPECT_EQ(same_full.stats.mb_skipped, same_full.stats.macroblocks);
  EXPECT_GT(same_full.stats.sad_evaluations, 0);
  EXPECT_EQ(same_early.stats.sad_evaluations, 0);
  EXPECT_EQ(same_early.bytes, same_full.bytes);
}

// Intra macroblocks beside inter ones predict from their reconstructed samples (docs/codec.md
// 3.7): a face whose right part no reference holds mixes both, and decodes exactly with
// every mode, with planar and DC only (the b-intra-prediction ablation) and with the
// narrowed intra searches of the faster speeds.
TEST(BFrame, IntraMacroblocksPredictFromInterNeighboursAndDecodeExactly) {
  const int w = 96, h = 80, q = 120;
  const ImageYCbCr420 reference = decoded_intra(textured_crop(w, h, 40, 40), q - 40);
  ImageYCbCr420 source = textured_crop(w, h, 44, 40);
  const ImageYCbCr420 other = textured_crop(w, h, 0, 0, 555);
  for (int y = 0; y < h; ++y) {
    for (int x = 40; x < w; ++x) source.y[static_cast<size_t>(y) * w + x] = other.y[static_cast<size_t>(y) * w + x];
  }
  // Every mode; planar and DC only; every mode with the narrowed partition search and
  // the RDOQ pass in the partition chosen first.
  for (int setting : {0, 1, 2}) {
    BFrameParams params;
    params.qindex = q;
    params.intra_prediction = setting != 1;
    if (setting == 2) {
      params.intra_rectangular_trials = 1;
      params.intra_small_trials = 1;
      params.keep_intra_partition = true;
    }
    ImageYCbCr420 reconstruction;
    BFrameStats stats;
    const std::vector<uint8_t> bytes =
        encode_b_frame(source, reference, nullptr,
                       candidate_hints(uniform_candidates(w, h, {MotionVector{16, 0}}), {}), params,
                       &reconstruction, &stats);
    EXPECT_GE(stats.mb_intra, 6) << "of " << stats.macroblocks;
    EXPECT_GE(stats.mb_forward + stats.mb_skipped, 6) << "of " << stats.macroblocks;
    ImageYCbCr420 decoded;
    std::vector<MacroblockMode> modes;
    ASSERT_TRUE(decode_b_frame(bytes, w, h, reference, nullptr, &decoded, &modes).ok());
    expect_same_image(decoded, reconstruction);
    EXPECT_EQ(modes, stats.modes);
    EXPECT_GT(psnr(source.y, decoded.y), 30.0);
  }
}

TEST(BFrame, DecoderMatchesEncoderBitExactlyForOddSizes) {
  const int sizes[][2] = {{37, 29}, {1, 1}, {16, 16}, {17, 40}, {70, 9}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const ImageYCbCr420 source = textured_crop(w, h, 50, 50);
    const ImageYCbCr420 ref0 = decoded_intra(textured_crop(w, h, 47, 51), 6);
    const ImageYCbCr420 ref1 = decoded_intra(textured_crop(w, h, 52, 48), 6);
    // Varied candidates: the true motion, quarter-pel and far-outside vectors.
    FaceCandidates c0 =
        uniform_candidates(w, h, {MotionVector{-12, 4}, MotionVector{-11, 5}, MotionVector{-1800, 80}});
    FaceCandidates c1 = uniform_candidates(w, h, {MotionVector{8, -8}, MotionVector{31000, -31000}});
    if (c1.size() > 1) c1[1].clear();
    for (int references = 1; references <= 2; ++references) {
      for (bool refine : {false, true}) {
        BFrameParams params;
        params.qindex = references == 1 ? 106 : 147;
        params.sub_pel_refinement = refine;
        ImageYCbCr420 reconstruction;
        BFrameStats stats;
        const ImageYCbCr420* second = references == 2 ? &ref1 : nullptr;
        const std::vector<uint8_t> bytes =
            encode_b_frame(source, ref0, second, candidate_hints(c0, c1), params, &reconstruction, &stats);
        ASSERT_FALSE(bytes.empty());
        ImageYCbCr420 decoded;
        std::vector<MacroblockMode> modes;
        const Status status = decode_b_frame(bytes, w, h, ref0, second, &decoded, &modes);
        ASSERT_TRUE(status.ok()) << status.to_string() << " " << w << "x" << h;
        expect_same_image(decoded, reconstruction);
        EXPECT_EQ(modes, stats.modes);
        EXPECT_GT(psnr(source.y, decoded.y), 30.0) << w << "x" << h << " refs " << references;
      }
    }
  }
}

TEST(BFrame, HeaderAndReferenceCountAreChecked) {
  const int w = 32, h = 32;
  const ImageYCbCr420 source = textured_crop(w, h, 3, 3), ref = textured_crop(w, h, 4, 3);
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, ref, nullptr, candidate_hints(uniform_candidates(w, h, {MotionVector{2, 0}}), {}),
                     BFrameParams{}, nullptr, nullptr);
  ASSERT_GE(bytes.size(), static_cast<size_t>(kBFrameHeaderBytes));
  BFrameHeader header;
  ASSERT_TRUE(parse_b_frame_header(bytes, &header).ok());
  EXPECT_EQ(header.reference_count, 1);
  EXPECT_EQ(header.qindex, BFrameParams{}.qindex);
  EXPECT_EQ(bytes[0], kBidirectionalTypeBit | kBFrameSyntaxVersion);

  ImageYCbCr420 out;
  EXPECT_EQ(decode_b_frame(bytes, w, h, ref, &ref, &out).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(decode_b_frame(bytes, w, h + 1, ref, nullptr, &out).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(decode_b_frame(bytes, 0, h, ref, nullptr, &out).code(), ErrorCode::kInvalidArgument);
  std::vector<uint8_t> changed = bytes;
  changed[0] = kBidirectionalTypeBit | (kBFrameSyntaxVersion + 1);  // a later syntax
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kUnsupported);
  changed[0] = kBidirectionalTypeBit | (kBFrameSyntaxVersion - 1);  // older entropy coding
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kUnsupported);
  changed = bytes;
  changed[kBFrameReferencesByte] |= 0x80;  // a warp mask naming reference 1 of a one-reference frame
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kCorruptData);
  changed = bytes;
  changed[kBFrameReferencesByte] |= 0x07;  // a reference border of 7 units
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kCorruptData);
  changed = bytes;
  changed[kBFrameReferencesByte] |= 0x18;  // interpolation filter 3
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kCorruptData);
  // The header's bytes are those its fields serialize to.
  const auto again = serialize_b_frame_header(header);
  EXPECT_TRUE(std::equal(again.begin(), again.end(), bytes.begin()));
  changed = bytes;
  changed[kBFrameFlagsByte] = 32;  // a flag this decoder does not know
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kCorruptData);
  changed[kBFrameFlagsByte] =
      static_cast<uint8_t>(bytes[kBFrameFlagsByte] ^ kLoopFilterDeblocking);  // valid either way
  EXPECT_TRUE(decode_b_frame(changed, w, h, ref, nullptr, &out).ok());
  changed = bytes;
  changed[0] = kBFrameSyntaxVersion;  // the type bit says intra
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kCorruptData);
  // Zeros appended: up to kImplicitZeroBytes the decoder may read them as the ones left
  // out at the end; beyond, they are trailing bytes.
  changed = bytes;
  changed.insert(changed.end(), kImplicitZeroBytes + 1, 0);
  EXPECT_EQ(decode_b_frame(changed, w, h, ref, nullptr, &out).code(), ErrorCode::kCorruptData);

  // The encoder refuses inconsistent images.
  EXPECT_TRUE(encode_b_frame(source, textured_crop(w, h + 2, 0, 0), nullptr, candidate_hints({}, {}),
                             BFrameParams{}, nullptr, nullptr)
                  .empty());
  EXPECT_TRUE(
      encode_b_frame(ImageYCbCr420{}, ref, nullptr, candidate_hints({}, {}), BFrameParams{}, nullptr, nullptr)
          .empty());
}

TEST(BFrame, GarbageNeverCrashesTheDecoder) {
  const int w = 48, h = 40;
  const ImageYCbCr420 source = textured_crop(w, h, 10, 10);
  const ImageYCbCr420 ref0 = textured_crop(w, h, 12, 9), ref1 = textured_crop(w, h, 8, 11);
  BFrameParams params;
  params.qindex = 96;
  const std::vector<uint8_t> valid =
      encode_b_frame(source, ref0, &ref1,
                     candidate_hints(uniform_candidates(w, h, {MotionVector{8, -4}}),
                                     uniform_candidates(w, h, {MotionVector{-8, 4}})),
                     params, nullptr, nullptr);
  ASSERT_GT(valid.size(), 32u);  // enough payload for the damage below to reach the levels
  ImageYCbCr420 out;
  std::vector<MacroblockMode> modes;
  // Cuts decode to a whole frame or are rejected; all but one of those by more than the
  // final zeros are rejected (measured: one).
  const int undetected = undetected_truncations(valid, [&](const std::vector<uint8_t>& cut) {
    const bool ok = decode_b_frame(cut, w, h, ref0, &ref1, &out, &modes).ok();
    if (ok) EXPECT_EQ(out.y.size(), source.y.size());
    return ok;
  });
  EXPECT_LE(undetected, 1) << "of " << valid.size() << " cuts";
  std::mt19937 rng(5);
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<uint8_t> bytes = valid;
    const int flips = 1 + trial % 4;
    for (int f = 0; f < flips; ++f) {
      bytes[kBFrameHeaderBytes + rng() % (bytes.size() - kBFrameHeaderBytes)] ^=
          static_cast<uint8_t>(1u << (rng() % 8));
    }
    if (decode_b_frame(bytes, w, h, ref0, &ref1, &out, &modes).ok()) {
      ++accepted;
      EXPECT_EQ(out.y.size(), static_cast<size_t>(w * h));
      EXPECT_EQ(modes.size(), 9u);
    }
  }
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<uint8_t> bytes(static_cast<size_t>(kBFrameHeaderBytes + rng() % 400));
    for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
    BFrameHeader header;  // bare references (border 0), two of them
    header.qindex = static_cast<int>(rng() % 256);
    header.loop_filters = static_cast<int>(rng() & kLoopFilterDeblocking);
    header.inter_transform_sizes = (rng() & 1) != 0;
    header.filter = static_cast<InterpolationFilter>(rng() % kInterpolationFilterCount);
    header.reference_count = 2;
    const auto header_bytes = serialize_b_frame_header(header);
    std::copy(header_bytes.begin(), header_bytes.end(), bytes.begin());
    if (testing::decodes_whole_or_refused(bytes, w, h, ref0, &ref1, "trial " + std::to_string(trial))) {
      ++accepted;
    } else {
      ++rejected;
    }
  }
  // Random payloads behind a valid header: most are refused (trailing bytes, invalid
  // levels), and every one decodes the same way twice.
  EXPECT_GT(rejected, 0) << accepted << " accepted";
}

// Half-pel luma averages of a reference: what a smoothing filter predicts exactly and
// the sharp regular filter does not.
ImageYCbCr420 half_pel_blur(const ImageYCbCr420& image) {
  ImageYCbCr420 out = image;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t i = static_cast<size_t>(y) * image.width + x;
      const int right = image.y[i + (x + 1 < image.width ? 1 : 0)];
      out.y[i] = static_cast<uint8_t>((image.y[i] + right + 1) / 2);
    }
  }
  return out;
}

// Squared error of all three planes plus the encoder's lambda times the bits: what the
// encoder's choices minimize.
double rd_cost(const ImageYCbCr420& source, const ImageYCbCr420& decoded, const std::vector<uint8_t>& bytes,
               const BFrameParams& params) {
  double squared = 0;
  for (size_t i = 0; i < source.y.size(); ++i) squared += std::pow(source.y[i] - decoded.y[i], 2);
  for (size_t i = 0; i < source.cb.size(); ++i) {
    squared += std::pow(source.cb[i] - decoded.cb[i], 2) + std::pow(source.cr[i] - decoded.cr[i], 2);
  }
  const double scale = quantizer_scale_q8(params.qindex) / 256.0;
  return squared + params.lambda_factor * scale * scale * 8.0 * static_cast<double>(bytes.size());
}

TEST(BFrame, SwitchableFilterPicksASmootherBankAndDecodesBitExactly) {
  const int w = 64, h = 48;
  const ImageYCbCr420 ref = decoded_intra(textured_crop(w, h, 20, 20), 83);
  const ImageYCbCr420 source = half_pel_blur(ref);
  const FaceCandidates candidates = uniform_candidates(w, h, {MotionVector{2, 0}});
  BFrameParams params;
  params.qindex = 115;  // quantizer scale 6
  params.sub_pel_refinement = false;
  std::vector<double> costs;
  for (bool switchable : {false, true}) {
    params.switchable_filter = switchable;
    ImageYCbCr420 reconstruction, decoded;
    const std::vector<uint8_t> bytes =
        encode_b_frame(source, ref, nullptr, candidate_hints(candidates, {}), params, &reconstruction, nullptr);
    BFrameHeader header;
    ASSERT_TRUE(parse_b_frame_header(bytes, &header).ok());
    EXPECT_EQ(header.filter == InterpolationFilter::kRegular, !switchable);
    ASSERT_TRUE(decode_b_frame(bytes, w, h, ref, nullptr, &decoded).ok());
    expect_same_image(decoded, reconstruction);
    costs.push_back(rd_cost(source, decoded, bytes, params));

    // The decoder predicts through the bank the header names: another bank, other pixels.
    std::vector<uint8_t> other = bytes;
    BFrameHeader other_header = header;
    other_header.filter =
        static_cast<InterpolationFilter>((static_cast<int>(header.filter) + 1) % kInterpolationFilterCount);
    const auto other_bytes = serialize_b_frame_header(other_header);
    std::copy(other_bytes.begin(), other_bytes.end(), other.begin());
    ImageYCbCr420 other_decoded;
    ASSERT_TRUE(decode_b_frame(other, w, h, ref, nullptr, &other_decoded).ok());
    EXPECT_FALSE(other_decoded.y == decoded.y);
  }
  EXPECT_LT(costs[1], costs[0]);
}

// The reference moved by (dx, dy) whole pixels, its luma plus an offset per macroblock
// and a gentle ramp: a residual one 16x16 transform block carries in a few coefficients.
ImageYCbCr420 shifted_with_ramp(const ImageYCbCr420& reference, int dx, int dy) {
  ImageYCbCr420 out = reference;
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      const int sx = std::clamp(x + dx, 0, reference.width - 1), sy = std::clamp(y + dy, 0, reference.height - 1);
      const int ramp = 10 * ((x / 16 + y / 16) % 3) - 10 + (x % 16) / 4;
      out.y[static_cast<size_t>(y) * reference.width + x] = static_cast<uint8_t>(
          std::clamp(reference.y[static_cast<size_t>(sy) * reference.width + sx] + ramp, 0, 255));
    }
  }
  return out;
}

// A frame coded from `ref` (whole-pixel motion 0) without and with inter transform sizes
// at `qindex`: per setting its statistics and rate-distortion cost. Checks on the way
// that the header flag follows the setting and decides the parse, and that each payload
// decodes to the encoder's reconstruction.
struct SizesRun {
  BFrameStats stats;
  double cost = 0;
};

std::array<SizesRun, 2> code_without_and_with_sizes(const ImageYCbCr420& source, const ImageYCbCr420& ref,
                                                    int qindex) {
  const int w = source.width, h = source.height;
  const FaceCandidates candidates = uniform_candidates(w, h, {MotionVector{0, 0}});
  BFrameParams params;
  params.qindex = qindex;
  std::array<SizesRun, 2> runs;
  for (int sizes_on = 0; sizes_on < 2; ++sizes_on) {
    params.inter_transform_sizes = sizes_on != 0;
    ImageYCbCr420 reconstruction, decoded;
    BFrameStats& stats = runs[sizes_on].stats;
    const std::vector<uint8_t> bytes =
        encode_b_frame(source, ref, nullptr, candidate_hints(candidates, {}), params, &reconstruction, &stats);
    BFrameHeader header;
    EXPECT_TRUE(parse_b_frame_header(bytes, &header).ok());
    EXPECT_EQ(header.inter_transform_sizes, sizes_on != 0);
    std::vector<MacroblockMode> modes;
    EXPECT_TRUE(decode_b_frame(bytes, w, h, ref, nullptr, &decoded, &modes).ok());
    expect_same_image(decoded, reconstruction);
    EXPECT_EQ(modes, stats.modes);
    runs[sizes_on].cost = rd_cost(source, decoded, bytes, params);

    // The flag decides how the payload parses: flipped, the frame reads otherwise.
    std::vector<uint8_t> flipped = bytes;
    flipped[kBFrameFlagsByte] ^= kInterTransformSizesFlag;
    ImageYCbCr420 other;
    const Status status = decode_b_frame(flipped, w, h, ref, nullptr, &other);
    EXPECT_TRUE(!status.ok() || other.y != decoded.y);
  }
  return runs;
}

TEST(BFrame, SmoothResidualsTakeOne16x16LumaBlockAndDecodeExactly) {
  const ImageYCbCr420 ref = decoded_intra(textured_crop(128, 96, 30, 30), 100);
  const std::array<SizesRun, 2> runs = code_without_and_with_sizes(shifted_with_ramp(ref, 0, 0), ref, 170);
  EXPECT_EQ(runs[0].stats.mb_luma_16x16, 0);
  EXPECT_GE(runs[1].stats.mb_luma_16x16, 6) << "of " << runs[1].stats.macroblocks;
  // The 16x16 blocks pay by the measure the encoder minimizes.
  EXPECT_LT(runs[1].cost, runs[0].cost);
}

// The reference's luma with a small bright spot in the top-left corner of every 8x8
// block: a residual that one 4x4 transform block of four carries.
ImageYCbCr420 with_spots(const ImageYCbCr420& reference) {
  ImageYCbCr420 out = reference;
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      if (x % 8 >= 3 || y % 8 >= 3) continue;
      uint8_t& sample = out.y[static_cast<size_t>(y) * reference.width + x];
      sample = static_cast<uint8_t>(std::min(255, sample + 40));
    }
  }
  return out;
}

TEST(BFrame, LocalResidualsTakeFour4x4BlocksAndDecodeExactly) {
  const ImageYCbCr420 ref = decoded_intra(textured_crop(64, 48, 30, 30), 100);
  const std::array<SizesRun, 2> runs = code_without_and_with_sizes(with_spots(ref), ref, 120);
  EXPECT_EQ(runs[0].stats.luma_blocks_4x4, 0);
  EXPECT_GE(runs[1].stats.luma_blocks_4x4, 24) << "of " << 4 * runs[1].stats.macroblocks << " luma blocks";
  EXPECT_LT(runs[1].cost, runs[0].cost);
}

TEST(BFrame, EmptyCandidateListsFallBackToZeroAndNeighbours) {
  const int w = 64, h = 48;
  const ImageYCbCr420 source = textured_crop(w, h, 30, 30),
                      reference = decoded_intra(textured_crop(w, h, 30, 30), 8);
  BFrameStats stats;
  ImageYCbCr420 reconstruction;
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, reference, nullptr, candidate_hints({}, {}), BFrameParams{}, &reconstruction, &stats);
  EXPECT_EQ(stats.candidates_evaluated, 0);
  EXPECT_GE(stats.mb_skipped, 10);  // the zero vector is right everywhere
  ImageYCbCr420 decoded;
  ASSERT_TRUE(decode_b_frame(bytes, w, h, reference, nullptr, &decoded).ok());
  expect_same_image(decoded, reconstruction);
}

TEST(BFrame, LogSearchCandidatesDriveTheSameEncoder) {
  const int w = 96, h = 64, q = 128;
  // Smooth shading, where a logarithmic search finds the motion (see codec_motion_test).
  auto shaded = [&](int ox, int oy) {
    ImageYCbCr420 image;
    image.width = w;
    image.height = h;
    image.y.resize(static_cast<size_t>(w) * h);
    image.cb.assign(static_cast<size_t>(w / 2) * (h / 2), 100);
    image.cr.assign(image.cb.size(), 160);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double v = 128 + 50 * std::sin((x + ox) / 11.0) * std::cos((y + oy) / 9.0) +
                         30 * std::sin((x + ox + y + oy) / 17.0);
        image.y[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
      }
    }
    return image;
  };
  const ImageYCbCr420 reference = decoded_intra(shaded(40, 40), q);
  const ImageYCbCr420 source = shaded(45, 37);
  const FaceCandidates searched = log_search_candidates(source, reference);
  BFrameParams params;
  params.qindex = q;
  params.intra_transform_types = false;  // as the intra frame compared with
  BFrameStats stats;
  ImageYCbCr420 reconstruction;
  const std::vector<uint8_t> bytes =
      encode_b_frame(source, reference, nullptr, candidate_hints(searched, {}), params, &reconstruction, &stats);
  // Against the DCT-only intra frame (transform types shrink this smooth shading's intra
  // frame further): the B-face codes it from the reference in under half the bytes.
  const std::vector<uint8_t> intra = encode_intra_frame(source, {.qindex = q, .transform_types = false}, nullptr);
  EXPECT_LT(bytes.size() * 2, intra.size()) << bytes.size() << " vs intra " << intra.size();
  EXPECT_EQ(stats.candidates_evaluated, stats.macroblocks);
  EXPECT_GT(psnr(source.y, reconstruction.y), 38.0);
}

// a where takes_b(x, y) is false, else b, with (x, y) a luma position (chroma sample
// (u, v) follows luma (2u, 2v)).
template <class TakesB>
ImageYCbCr420 mix(const ImageYCbCr420& a, const ImageYCbCr420& b, TakesB takes_b) {
  ImageYCbCr420 mixed = a;
  const int cw = (a.width + 1) / 2;
  for (size_t i = 0; i < a.y.size(); ++i) {
    const auto x = static_cast<int>(i % static_cast<size_t>(a.width));
    const auto y = static_cast<int>(i / static_cast<size_t>(a.width));
    if (takes_b(x, y)) mixed.y[i] = b.y[i];
  }
  for (size_t i = 0; i < a.cb.size(); ++i) {
    const auto u = static_cast<int>(i % static_cast<size_t>(cw)), v = static_cast<int>(i / static_cast<size_t>(cw));
    if (takes_b(2 * u, 2 * v)) {
      mixed.cb[i] = b.cb[i];
      mixed.cr[i] = b.cr[i];
    }
  }
  return mixed;
}

// Columns of 8 luma pixels alternate between two motions, so every macroblock holds two
// 8x16 halves moving differently: source(x, y) = a(x, y) where (x / 8) is even, else b.
ImageYCbCr420 column_mix(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  return mix(a, b, [](int x, int) { return (x / 8) % 2 != 0; });
}

// Per 8x8 block, the vector of its column's motion (what depth would give).
FaceCandidates column_block_candidates(int width, int height, MotionVector even, MotionVector odd) {
  const int blocks_x = 2 * ((width + 15) / 16), blocks_y = 2 * ((height + 15) / 16);
  FaceCandidates lists(static_cast<size_t>(blocks_x) * blocks_y);
  for (size_t i = 0; i < lists.size(); ++i) lists[i] = {(i % static_cast<size_t>(blocks_x)) % 2 == 0 ? even : odd};
  return lists;
}

TEST(BFramePartitions, SplitMotionIsCodedWithHalvesAndDecodedExactly) {
  const int w = 96, h = 64, q = 128;
  const MotionVector even{12, 8}, odd{-8, 4};
  const ImageYCbCr420 reference = decoded_intra(textured_crop(w, h, 40, 40), q);
  const ImageYCbCr420 source = column_mix(textured_crop(w, h, 43, 42), textured_crop(w, h, 38, 41));
  const FaceCandidates macroblock_lists = uniform_candidates(w, h, {even, odd});
  const FaceCandidates block_lists = column_block_candidates(w, h, even, odd);
  const std::array<ReferenceHints, 2> hints = {ReferenceHints{&macroblock_lists, &block_lists, nullptr},
                                               ReferenceHints{}};
  BFrameParams params;
  params.qindex = suggested_b_qindex(q);
  ImageYCbCr420 split_reconstruction, whole_reconstruction;
  BFrameStats split_stats, whole_stats;
  const std::vector<uint8_t> split =
      encode_b_frame(source, reference, nullptr, hints, params, &split_reconstruction, &split_stats);
  params.partitions = false;
  const std::vector<uint8_t> whole =
      encode_b_frame(source, reference, nullptr, hints, params, &whole_reconstruction, &whole_stats);
  EXPECT_EQ(whole_stats.mb_partitioned, 0);
  EXPECT_GE(split_stats.mb_partitioned, split_stats.macroblocks * 3 / 4);
  // Two exact predictions beat one vector and a residual (or intra) for each half.
  EXPECT_LT(split.size() * 2, whole.size()) << split.size() << " vs " << whole.size();
  EXPECT_GT(psnr(source.y, split_reconstruction.y), psnr(source.y, whole_reconstruction.y) - 0.5);
  EXPECT_GT(psnr(source.y, split_reconstruction.y), 40.0);

  for (const auto* bytes : {&split, &whole}) {
    ImageYCbCr420 decoded;
    std::vector<MacroblockMode> modes;
    std::vector<Partition> partitions;
    const Status status = decode_b_frame(*bytes, w, h, reference, nullptr, &decoded, &modes, &partitions);
    ASSERT_TRUE(status.ok()) << status.to_string();
    expect_same_image(decoded, bytes == &split ? split_reconstruction : whole_reconstruction);
    EXPECT_EQ(modes, (bytes == &split ? split_stats : whole_stats).modes);
    ASSERT_EQ(partitions.size(), modes.size());
    EXPECT_EQ(std::count_if(partitions.begin(), partitions.end(),
                            [](Partition p) { return p != Partition::k16x16; }),
              (bytes == &split ? split_stats : whole_stats).mb_partitioned);
  }
}

TEST(BFramePartitions, PartitionsChooseTheirOwnReferenceAndDecodeExactly) {
  // Odd columns are seen only by reference 1, even ones only by reference 0, at odd
  // sizes (partial macroblocks at the right and bottom edges).
  const int sizes[][2] = {{77, 45}, {24, 40}, {120, 17}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const ImageYCbCr420 ref0 = decoded_intra(textured_crop(w, h, 40, 40), 115);
    const ImageYCbCr420 ref1 = decoded_intra(textured_crop(w, h, 60, 70, 99), 115);
    const ImageYCbCr420 source = column_mix(textured_crop(w, h, 43, 42), textured_crop(w, h, 61, 69, 99));
    const MotionVector to0{12, 8}, to1{4, -4};
    const FaceCandidates lists0 = uniform_candidates(w, h, {to0}), lists1 = uniform_candidates(w, h, {to1});
    const FaceCandidates blocks0 = column_block_candidates(w, h, to0, MotionVector{-40, 20});
    const FaceCandidates blocks1 = column_block_candidates(w, h, MotionVector{32, 0}, to1);
    const std::array<ReferenceHints, 2> hints = {ReferenceHints{&lists0, &blocks0, nullptr},
                                                 ReferenceHints{&lists1, &blocks1, nullptr}};
    BFrameParams params;
    params.qindex = 138;  // quantizer scale 10
    ImageYCbCr420 reconstruction;
    BFrameStats stats;
    const std::vector<uint8_t> bytes = encode_b_frame(source, ref0, &ref1, hints, params, &reconstruction, &stats);
    ASSERT_FALSE(bytes.empty());
    if (w >= 16) EXPECT_GE(stats.mb_partitioned, stats.macroblocks / 2) << w << "x" << h;
    EXPECT_GT(psnr(source.y, reconstruction.y), 36.0) << w << "x" << h;
    ImageYCbCr420 decoded;
    std::vector<MacroblockMode> modes;
    const Status status = decode_b_frame(bytes, w, h, ref0, &ref1, &decoded, &modes);
    ASSERT_TRUE(status.ok()) << status.to_string();
    expect_same_image(decoded, reconstruction);
    EXPECT_EQ(modes, stats.modes);
  }
}

TEST(BFrameSearchPlanes, SharedPlanesGiveTheBytesOfPlanesBuiltPerFace) {
  const int w = 77, h = 45;
  const ImageYCbCr420 ref0 = decoded_intra(textured_crop(w, h, 40, 40), 115);
  const ImageYCbCr420 ref1 = decoded_intra(textured_crop(w, h, 60, 70, 99), 115);
  const ImageYCbCr420 source = column_mix(textured_crop(w, h, 43, 42), textured_crop(w, h, 61, 69, 99));
  const FaceCandidates lists0 = uniform_candidates(w, h, {MotionVector{12, 8}, MotionVector{-3, 5}});
  const FaceCandidates lists1 = uniform_candidates(w, h, {MotionVector{4, -4}, MotionVector{1, 7}});
  BFrameParams params;
  params.qindex = 138;
  const auto encode = [&](const SearchPlanes* search0, const SearchPlanes* search1) {
    std::array<ReferenceHints, 2> hints = {ReferenceHints{&lists0, nullptr, nullptr},
                                           ReferenceHints{&lists1, nullptr, nullptr}};
    hints[0].search = search0;
    hints[1].search = search1;
    return encode_b_frame(source, ref0, &ref1, hints, params, nullptr, nullptr);
  };
  const std::vector<uint8_t> own = encode(nullptr, nullptr);
  ASSERT_FALSE(own.empty());
  const auto planes0 = b_frame_search_planes(ref0), planes1 = b_frame_search_planes(ref1);
  EXPECT_EQ(encode(planes0.get(), planes1.get()), own);
  // Planes of a face of another size are not used: the encoder builds its own.
  const auto other_size = b_frame_search_planes(decoded_intra(textured_crop(w + 16, h, 40, 40), 115));
  EXPECT_EQ(encode(other_size.get(), other_size.get()), own);
  // Planes of another face of the same size rank the vectors differently, and the frame
  // still decodes to the encoder's reconstruction.
  ImageYCbCr420 reconstruction, decoded;
  std::array<ReferenceHints, 2> swapped = {ReferenceHints{&lists0, nullptr, nullptr},
                                           ReferenceHints{&lists1, nullptr, nullptr}};
  swapped[0].search = planes1.get();
  swapped[1].search = planes0.get();
  const std::vector<uint8_t> bytes = encode_b_frame(source, ref0, &ref1, swapped, params, &reconstruction, nullptr);
  ASSERT_FALSE(bytes.empty());
  EXPECT_NE(bytes, own);  // the planes given are the ones searched
  ASSERT_TRUE(decode_b_frame(bytes, w, h, ref0, &ref1, &decoded).ok());
  expect_same_image(decoded, reconstruction);
}

TEST(BFramePartitions, DamagedPartitionedPayloadsAreRejectedOrDecoded) {
  const int w = 48, h = 32;
  const ImageYCbCr420 reference = textured_crop(w, h, 40, 40);
  const ImageYCbCr420 source = column_mix(textured_crop(w, h, 43, 42), textured_crop(w, h, 38, 41));
  const FaceCandidates lists = uniform_candidates(w, h, {MotionVector{12, 8}, MotionVector{-8, 4}});
  const FaceCandidates blocks = column_block_candidates(w, h, MotionVector{12, 8}, MotionVector{-8, 4});
  BFrameParams params;
  params.qindex = 115;  // quantizer scale 6
  BFrameStats stats;
  const std::vector<uint8_t> valid = encode_b_frame(source, reference, nullptr,
                                                    {ReferenceHints{&lists, &blocks, nullptr}, ReferenceHints{}},
                                                    params, nullptr, &stats);
  ASSERT_GT(stats.mb_partitioned, 0);
  ImageYCbCr420 out;
  // Cuts decode to a whole frame or are rejected; all but one of those by more than the
  // final zeros are rejected (measured: one).
  const int undetected = undetected_truncations(valid, [&](const std::vector<uint8_t>& cut) {
    const bool ok = decode_b_frame(cut, w, h, reference, nullptr, &out).ok();
    if (ok) EXPECT_EQ(out.y.size(), source.y.size());
    return ok;
  });
  EXPECT_LE(undetected, 1) << "of " << valid.size() << " cuts";
  // Every bit of the macroblock data flipped in turn: an error, or an image of the size.
  for (size_t bit = 8 * kBFrameHeaderBytes; bit < 8 * valid.size(); ++bit) {
    std::vector<uint8_t> bytes = valid;
    bytes[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
    const Status status = decode_b_frame(bytes, w, h, reference, nullptr, &out);
    if (status.ok()) {
      EXPECT_EQ(out.y.size(), static_cast<size_t>(w * h)) << bit;
    } else {
      EXPECT_EQ(status.code(), ErrorCode::kCorruptData) << bit;
    }
  }
}

// Rows of macroblocks alternate between two motions (a depth edge along every
// macroblock row): source = a in even macroblock rows, b in odd ones.
ImageYCbCr420 row_mix(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  return mix(a, b, [](int, int y) { return (y / 16) % 2 != 0; });
}

// The median of the left, top and top-right vectors takes the other row's motion there;
// the left macroblock's vector, second in the predictor list, is exact.
TEST(BFrame, VectorsTakeTheLeftPredictorWhereTheMedianIsWrongAndDecodeExactly) {
  const int w = 128, h = 96, q = 128;
  const MotionVector even{12, 8}, odd{-8, 4};
  const ImageYCbCr420 reference = decoded_intra(textured_crop(w, h, 40, 40), q);
  const ImageYCbCr420 source = row_mix(textured_crop(w, h, 43, 42), textured_crop(w, h, 38, 41));
  const int mbs_x = (w + 15) / 16;
  FaceCandidates candidates(static_cast<size_t>(mbs_x) * ((h + 15) / 16));
  for (size_t i = 0; i < candidates.size(); ++i) candidates[i] = {(i / mbs_x) % 2 == 0 ? even : odd};
  BFrameParams params;
  params.qindex = suggested_b_qindex(q);
  ImageYCbCr420 listed_reconstruction, median_reconstruction;
  BFrameStats listed_stats, median_stats;
  const std::vector<uint8_t> listed = encode_b_frame(source, reference, nullptr, candidate_hints(candidates, {}),
                                                     params, &listed_reconstruction, &listed_stats);
  params.vector_predictors = false;
  const std::vector<uint8_t> median = encode_b_frame(source, reference, nullptr, candidate_hints(candidates, {}),
                                                     params, &median_reconstruction, &median_stats);
  ASSERT_FALSE(listed.empty());
  ASSERT_FALSE(median.empty());
  // Each row after the first codes the jump between the rows' motions once (its first
  // macroblock) instead of at every macroblock, or skips with the left vector.
  EXPECT_LT(listed.size() * 3, median.size() * 2) << listed.size() << " vs " << median.size();
  EXPECT_GT(psnr(source.y, listed_reconstruction.y), psnr(source.y, median_reconstruction.y) - 0.2);
  EXPECT_GT(listed_stats.mb_skipped, median_stats.mb_skipped);
  for (const auto* bytes : {&listed, &median}) {
    ImageYCbCr420 decoded;
    std::vector<MacroblockMode> modes;
    ASSERT_TRUE(decode_b_frame(*bytes, w, h, reference, nullptr, &decoded, &modes).ok());
    expect_same_image(decoded, bytes == &listed ? listed_reconstruction : median_reconstruction);
    EXPECT_EQ(modes, (bytes == &listed ? listed_stats : median_stats).modes);
  }
}

// Motion away from the point e = (width, height / 2) (pixel-edge coordinates), as
// planes facing a camera that moves back along its view see it: source(p) =
// reference(p + k (p - e)), k a different depth's scale in each macroblock. Every
// motion lies on the epipolar line through e, its length varying with depth.
double depth_scale(int mx, int my) { return 0.02 + 0.015 * ((7 * mx + 3 * my) % 5); }

ImageYCbCr420 moved_back(const ImageYCbCr420& reference) {
  ImageYCbCr420 out = reference;
  auto sample = [](const std::vector<uint8_t>& plane, int w, int h, double x, double y) {
    x = std::clamp(x, 0.0, w - 1.0);
    y = std::clamp(y, 0.0, h - 1.0);
    const int ix = std::min(static_cast<int>(x), w - 2), iy = std::min(static_cast<int>(y), h - 2);
    const double fx = x - ix, fy = y - iy;
    auto at = [&](int u, int v) { return static_cast<double>(plane[static_cast<size_t>(v) * w + u]); };
    return static_cast<uint8_t>(std::lround((1 - fy) * ((1 - fx) * at(ix, iy) + fx * at(ix + 1, iy)) +
                                            fy * ((1 - fx) * at(ix, iy + 1) + fx * at(ix + 1, iy + 1))));
  };
  // scale: 1 for luma, 2 for chroma (a macroblock is 8 chroma samples wide).
  auto warp = [&](const std::vector<uint8_t>& plane, std::vector<uint8_t>& target, int w, int h, int scale) {
    const double ex = w, ey = h / 2.0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double k = depth_scale(x * scale / 16, y * scale / 16);
        const double px = x + 0.5, py = y + 0.5;
        target[static_cast<size_t>(y) * w + x] =
            sample(plane, w, h, px + k * (px - ex) - 0.5, py + k * (py - ey) - 0.5);
      }
    }
  };
  warp(reference.y, out.y, reference.width, reference.height, 1);
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  warp(reference.cb, out.cb, cw, ch, 2);
  warp(reference.cr, out.cr, cw, ch, 2);
  return out;
}

TEST(BFrame, EpipolarLinesCodeMotionAlongThemInFewerBytesAndDecodeExactly) {
  const int w = 128, h = 96, q = 96;
  const ImageYCbCr420 texture = textured_crop(w, h, 20, 30);
  const ImageYCbCr420 reference = decoded_intra(texture, q);
  const ImageYCbCr420 source = moved_back(texture);
  // Per macroblock the motion of its top-left pixel and of its centre, as depth gives
  // them: each on its own pixel's line, the first off the centre's.
  FaceCandidates candidates;
  for (int my = 0; my < h / 16; ++my) {
    for (int mx = 0; mx < w / 16; ++mx) {
      CandidateList list;
      const double k = depth_scale(mx, my);
      for (const double offset : {0.5, 8.0}) {
        const double px = 16 * mx + offset, py = 16 * my + offset;
        list.push_back(MotionVector{static_cast<int16_t>(std::lround(4 * k * (px - w))),
                                    static_cast<int16_t>(std::lround(4 * k * (py - h / 2.0)))});
      }
      candidates.push_back(list);
    }
  }
  const EpipolarLines lines{1, -1, 0};
  BFrameParams params;
  params.qindex = suggested_b_qindex(q);
  auto encode = [&](bool with_lines, ImageYCbCr420* reconstruction) {
    params.epipolar_lines = with_lines;
    const std::array<ReferenceHints, 2> hints = {ReferenceHints{&candidates, nullptr, nullptr, lines},
                                                 ReferenceHints{}};
    return encode_b_frame(source, reference, nullptr, hints, params, reconstruction, nullptr);
  };
  ImageYCbCr420 with_lines, without_lines;
  const std::vector<uint8_t> bytes = encode(true, &with_lines);
  const std::vector<uint8_t> plain = encode(false, &without_lines);
  BFrameHeader header;
  ASSERT_TRUE(parse_b_frame_header(bytes, &header).ok());
  EXPECT_TRUE(header.epipolar_lines);
  ASSERT_TRUE(parse_b_frame_header(plain, &header).ok());
  EXPECT_FALSE(header.epipolar_lines);
  // 5 % smaller when written (224 bytes against 236 at equal PSNR).
  EXPECT_LE(bytes.size() * 100, plain.size() * 97) << bytes.size() << " vs " << plain.size();
  EXPECT_GT(psnr(source.y, with_lines.y), psnr(source.y, without_lines.y) - 0.3)
      << psnr(source.y, with_lines.y) << " vs " << psnr(source.y, without_lines.y);
  ImageYCbCr420 decoded;
  ASSERT_TRUE(decode_b_frame(bytes, w, h, reference, nullptr, &decoded).ok());
  expect_same_image(decoded, with_lines);
  ASSERT_TRUE(decode_b_frame(plain, w, h, reference, nullptr, &decoded).ok());
  expect_same_image(decoded, without_lines);
}

TEST(BFrame, SuggestedQIndex) {
  EXPECT_EQ(suggested_b_qindex(128), 170);
  EXPECT_EQ(suggested_b_qindex(0), 42);
  EXPECT_EQ(suggested_b_qindex(213), 255);
  EXPECT_EQ(suggested_b_qindex(250), 255);
  EXPECT_EQ(suggested_b_qindex(-5), 37);
  // 42 indices make the step about 2.5 times coarser, as the MPEG-2 style ratio did.
  for (int q : {0, 40, 100, 150, 200}) {
    const double ratio = double(quantizer_scale_q8(q + 42)) / quantizer_scale_q8(q);
    EXPECT_NEAR(ratio, 2.48, 0.05) << q;
  }
}

TEST(BFrame, AdaptedQIndexShrinksTheOffsetAsMoreMacroblocksAreIntra) {
  EXPECT_EQ(adapted_b_qindex(128, 0.0), suggested_b_qindex(128));
  EXPECT_EQ(adapted_b_qindex(128, 1.0), 128 + kMinBQIndexOffset);
  int previous = adapted_b_qindex(128, 0.0);
  for (int percent = 1; percent <= 100; ++percent) {
    const int qindex = adapted_b_qindex(128, percent / 100.0);
    EXPECT_LE(qindex, previous) << percent;
    EXPECT_GE(qindex, 128 + kMinBQIndexOffset) << percent;
    previous = qindex;
  }
  EXPECT_LT(adapted_b_qindex(128, 0.5), suggested_b_qindex(128));
  // Out-of-range shares and indices are clamped; a NaN share keeps the default.
  EXPECT_EQ(adapted_b_qindex(128, -1.0), suggested_b_qindex(128));
  EXPECT_EQ(adapted_b_qindex(128, 7.0), 128 + kMinBQIndexOffset);
  EXPECT_EQ(adapted_b_qindex(128, std::nan("")), suggested_b_qindex(128));
  EXPECT_EQ(adapted_b_qindex(250, 1.0), 255);
}

}  // namespace
}  // namespace svc::codec
