// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/intra_frame.h"
#include "codec/common/warp_prediction.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/intra_encoder.h"
#include "support/damaged_payload.h"
#include "support/reference_hints.h"

namespace svc::codec {
namespace {

// A smooth continuous texture: value at any real position (pixel-index coordinates).
double texture_at(double x, double y) {
  return 128 + 45 * std::sin(0.21 * x + 0.05 * y) + 30 * std::cos(0.13 * y - 0.07 * x) +
         20 * std::sin(0.031 * x * 1.7 + 0.043 * y);
}

// image(x, y) = texture(map(x, y)) for luma; chroma samples the same at pixel-pair centres.
template <typename Map>
ImageYCbCr420 sample_image(int width, int height, Map map) {
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.resize(static_cast<size_t>(cw) * ch);
  image.cr.resize(image.cb.size());
  auto clamp_byte = [](double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0))); };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double u, v;
      map(x, y, &u, &v);
      image.y[static_cast<size_t>(y) * width + x] = clamp_byte(texture_at(u, v));
    }
  }
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      double u, v;
      map(2 * x + 0.5, 2 * y + 0.5, &u, &v);
      image.cb[static_cast<size_t>(y) * cw + x] = clamp_byte(texture_at(0.5 * u + 40, 0.5 * v));
      image.cr[static_cast<size_t>(y) * cw + x] = clamp_byte(255 - texture_at(0.5 * v, 0.5 * u + 9));
    }
  }
  return image;
}

ImageYCbCr420 random_image(int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.resize(static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2));
  image.cr.resize(image.cb.size());
  for (auto* plane : {&image.y, &image.cb, &image.cr}) {
    for (uint8_t& v : *plane) v = static_cast<uint8_t>(rng());
  }
  return image;
}

ImageYCbCr420 decoded_intra(const ImageYCbCr420& image, int qindex) {
  ImageYCbCr420 reconstruction;
  encode_intra_frame(image, CodingParams{qindex}, &reconstruction);
  return reconstruction;
}

// The perspective map of a textured plane: the point seen at (x, y) of the current face is
// seen at H(x, y) of the reference face.
struct Homography {
  double m[9];
  void apply(double x, double y, double* u, double* v) const {
    const double w = m[6] * x + m[7] * y + m[8];
    *u = (m[0] * x + m[1] * y + m[2]) / w;
    *v = (m[3] * x + m[4] * y + m[5]) / w;
  }
};

WarpField exact_nodes(int width, int height, const Homography& h) {
  WarpField field;
  field.nodes_x = (width + 15) / 16 + 1;
  field.nodes_y = (height + 15) / 16 + 1;
  for (int j = 0; j < field.nodes_y; ++j) {
    for (int i = 0; i < field.nodes_x; ++i) {
      const double x = 16 * i - 0.5, y = 16 * j - 0.5;
      double u, v;
      h.apply(x, y, &u, &v);
      field.nodes.push_back(
          WarpNode{static_cast<int32_t>(std::lround((u - x) * 8)), static_cast<int32_t>(std::lround((v - y) * 8))});
    }
  }
  return field;
}

// Per macroblock the distinct quarter-pel vectors of the exact flow, most frequent first: what
// a depth-driven encoder offers without warping.
FaceCandidates exact_candidates(int width, int height, const Homography& h) {
  const int mbs_x = (width + 15) / 16, mbs_y = (height + 15) / 16;
  FaceCandidates candidates(static_cast<size_t>(mbs_x) * mbs_y);
  for (int my = 0; my < mbs_y; ++my) {
    for (int mx = 0; mx < mbs_x; ++mx) {
      std::vector<std::pair<int, MotionVector>> counted;
      for (int y = 16 * my; y < std::min(height, 16 * my + 16); ++y) {
        for (int x = 16 * mx; x < std::min(width, 16 * mx + 16); ++x) {
          double u, v;
          h.apply(x, y, &u, &v);
          const MotionVector mv{static_cast<int16_t>(std::lround((u - x) * 4)),
                                static_cast<int16_t>(std::lround((v - y) * 4))};
          auto it = std::find_if(counted.begin(), counted.end(), [&](const auto& c) { return c.second == mv; });
          if (it == counted.end()) {
            counted.push_back({1, mv});
          } else {
            ++it->first;
          }
        }
      }
      std::stable_sort(counted.begin(), counted.end(),
                       [](const auto& a, const auto& b) { return a.first > b.first; });
      for (const auto& c : counted) candidates[static_cast<size_t>(my) * mbs_x + mx].push_back(c.second);
    }
  }
  return candidates;
}

// A floor-like plane seen obliquely: strong vertical perspective change and some shear.
// It maps the whole current face inside the reference face.
const Homography kPlane = {{0.9, 0.04, 5.0, 0.01, 0.95, 3.0, 0.0003, 0.0008, 1.0}};

// The fast path predicts runs of sub-blocks with equal vectors as one block; the small
// spreads make such runs common, the large ones rare.
TEST(WarpPrediction, FastMatchesReferenceOnRandomData) {
  std::mt19937 rng(11);
  const int sizes[][2] = {{48, 32}, {37, 21}, {16, 16}, {5, 3}};
  int trials_with_runs = 0;
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const ImageYCbCr420 reference = random_image(w, h, static_cast<uint32_t>(w * 31 + h));
    for (int trial = 0; trial < 300; ++trial) {
      const int mx = static_cast<int>(rng() % ((w + 15) / 16)), my = static_cast<int>(rng() % ((h + 15) / 16));
      WarpCorners corners;
      const int spread = std::array{4, 40, 400, 4000}[static_cast<size_t>(trial % 4)];
      const int base_x = static_cast<int>(rng() % 801) - 400, base_y = static_cast<int>(rng() % 801) - 400;
      for (WarpNode& node : corners) {
        node.x = base_x + static_cast<int>(rng() % (2 * spread + 1)) - spread;
        node.y = base_y + static_cast<int>(rng() % (2 * spread + 1)) - spread;
      }
      MacroblockIntermediate fast, plain;
      predict_warp_macroblock(reference, mx, my, corners, &fast);
      predict_warp_macroblock_reference(reference, mx, my, corners, &plain);
      ASSERT_EQ(fast.y, plain.y) << w << "x" << h << " trial " << trial;
      ASSERT_EQ(fast.cb, plain.cb) << w << "x" << h << " trial " << trial;
      ASSERT_EQ(fast.cr, plain.cr) << w << "x" << h << " trial " << trial;
      int16_t luma[256];
      predict_warp_macroblock_luma(reference, mx, my, corners, luma);
      ASSERT_TRUE(std::equal(luma, luma + 256, plain.y.begin()));
      bool run = false;
      for (int b = 4; b < 32; b += 8) {
        run = run || warp_subblock_vector(corners, 4, b) == warp_subblock_vector(corners, 12, b);
      }
      trials_with_runs += run;
    }
  }
  EXPECT_GT(trials_with_runs, 200);  // of 1,200
}

TEST(WarpPrediction, UniformNodesEqualTranslation) {
  // Equal nodes on the quarter-pel grid give every sub-block the same vector: the
  // translation, exactly, luma and chroma.
  const int w = 64, h = 48;
  const ImageYCbCr420 reference = random_image(w, h, 3);
  for (const WarpNode node : {WarpNode{8, -16}, WarpNode{-24, 40}, WarpNode{2, 14}, WarpNode{-6, 6}}) {
    const WarpCorners corners = {node, node, node, node};
    const MotionVector vector{static_cast<int16_t>(node.x / 2), static_cast<int16_t>(node.y / 2)};
    MacroblockIntermediate warped, translated;
    predict_warp_macroblock(reference, 1, 1, corners, &warped);
    predict_macroblock(reference, 1, 1, vector, &translated);
    EXPECT_EQ(warped.y, translated.y);
    EXPECT_EQ(warped.cb, translated.cb);
    EXPECT_EQ(warped.cr, translated.cr);
  }
}

TEST(WarpPrediction, SubblockVectorsInterpolateTheCorners) {
  // Corners (0, 0), (64, 0), (0, 32), (64, 32) in 1/8 pel: the vector grows by 8 (1 pixel)
  // across the block horizontally and 4 vertically; sub-block centres sit at 1/8, 3/8, ...
  const WarpCorners corners = {WarpNode{0, 0}, WarpNode{64, 0}, WarpNode{0, 32}, WarpNode{64, 32}};
  // Luma (0, 0) at a = b = 4: x = 64 * 4/32 = 8 eighths = 4 quarters; y = 32 * 4/32 = 2.
  EXPECT_EQ(warp_subblock_vector(corners, 4, 4), (std::array<int, 2>{4, 2}));
  EXPECT_EQ(warp_subblock_vector(corners, 28, 20), (std::array<int, 2>{28, 10}));
  // Chroma (1, 1) at a = b = 24: x = 48 eighths = 24 quarters, y = 24 / 2 = 12.
  EXPECT_EQ(warp_subblock_vector(corners, 24, 24), (std::array<int, 2>{24, 12}));
  // Rounding: S = 1024 * 3 (3/8 pel everywhere) is 1.5 quarters, rounded up to 2;
  // -3/8 is -1.5, rounded up to -1 (floor after adding half).
  const WarpNode three{3, -3};
  EXPECT_EQ(warp_subblock_vector({three, three, three, three}, 12, 12), (std::array<int, 2>{2, -1}));
}

// Node fields that vary smoothly with some jitter and a jump, for bit-exactness tests.
WarpField test_field(int width, int height, int dx, int dy, uint32_t seed) {
  std::mt19937 rng(seed);
  WarpField field;
  field.nodes_x = (width + 15) / 16 + 1;
  field.nodes_y = (height + 15) / 16 + 1;
  for (int j = 0; j < field.nodes_y; ++j) {
    for (int i = 0; i < field.nodes_x; ++i) {
      int x = 8 * dx + i * 3 - j + static_cast<int>(rng() % 5) - 2,
          y = 8 * dy + j * 4 + static_cast<int>(rng() % 5) - 2;
      if (i == 2) x += 60;  // a discontinuity
      field.nodes.push_back(WarpNode{x, y});
    }
  }
  return field;
}

TEST(WarpBFrame, DecoderMatchesEncoderBitExactly) {
  const int sizes[][2] = {{37, 29}, {1, 1}, {16, 16}, {17, 40}, {70, 9}, {64, 48}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const Homography shifted = {{1.02, 0.01, 3.0, 0.0, 1.03, 2.0, 0.0, 0.0005, 1.0}};
    const ImageYCbCr420 source = sample_image(w, h, [](double x, double y, double* u, double* v) {
      *u = x;
      *v = y;
    });
    const ImageYCbCr420 ref0 = decoded_intra(
        sample_image(w, h, [&](double x, double y, double* u, double* v) { shifted.apply(x, y, u, v); }), 6);
    const ImageYCbCr420 ref1 = decoded_intra(sample_image(w, h,
                                                          [](double x, double y, double* u, double* v) {
                                                            *u = x - 2.5;
                                                            *v = y + 1;
                                                          }),
                                             6);
    const WarpField field0 = test_field(w, h, -3, -2, 1), field1 = test_field(w, h, 2, -1, 2);
    const FaceCandidates c0(static_cast<size_t>((w + 15) / 16) * ((h + 15) / 16),
                            CandidateList{MotionVector{-12, -8}});
    const FaceCandidates c1(c0.size(), CandidateList{MotionVector{10, -3}});
    for (int references = 1; references <= 2; ++references) {
      for (int fields = 0; fields < 3; ++fields) {  // both, only the first, only the second
        BFrameParams params;
        params.qindex = references == 1 ? 106 : 147;
        const ImageYCbCr420* second = references == 2 ? &ref1 : nullptr;
        ImageYCbCr420 reconstruction;
        BFrameStats stats;
        const std::vector<uint8_t> bytes = encode_b_frame(source, ref0, second,
                                                          candidate_hints(c0, c1, fields == 2 ? nullptr : &field0,
                                                                          fields == 1 ? nullptr : &field1),
                                                          params, &reconstruction, &stats);
        ASSERT_FALSE(bytes.empty());
        ImageYCbCr420 decoded;
        std::vector<MacroblockMode> modes;
        const Status status = decode_b_frame(bytes, w, h, ref0, second, &decoded, &modes);
        ASSERT_TRUE(status.ok()) << status.to_string() << " " << w << "x" << h;
        EXPECT_EQ(decoded.y, reconstruction.y) << w << "x" << h << " refs " << references << " fields " << fields;
        EXPECT_EQ(decoded.cb, reconstruction.cb);
        EXPECT_EQ(decoded.cr, reconstruction.cr);
        EXPECT_EQ(modes, stats.modes);
        BFrameHeader header;
        ASSERT_TRUE(parse_b_frame_header(bytes, &header).ok());
        const int expected_mask = (fields == 2 ? 0 : 1) | (references == 2 && fields != 1 ? 2 : 0);
        EXPECT_EQ(header.warp_mask, expected_mask);
        if (expected_mask == 0) EXPECT_EQ(stats.mb_warp, 0);
      }
    }
  }
}

TEST(WarpBFrame, PerspectivePlanePredictsAlmostPerfectly) {
  const int w = 128, h = 128, q = 128;
  // The reference shows the plane texture directly; the current face sees it through H.
  const ImageYCbCr420 original = sample_image(w, h, [](double x, double y, double* u, double* v) {
    *u = x;
    *v = y;
  });
  const ImageYCbCr420 reference = decoded_intra(original, q);
  const ImageYCbCr420 source =
      sample_image(w, h, [](double x, double y, double* u, double* v) { kPlane.apply(x, y, u, v); });
  const WarpField field = exact_nodes(w, h, kPlane);
  const FaceCandidates candidates = exact_candidates(w, h, kPlane);

  // The warped prediction alone is close to the source everywhere the plane is visible.
  double squared = 0;
  int samples = 0;
  for (int my = 0; my < h / 16; ++my) {
    for (int mx = 0; mx < w / 16; ++mx) {
      WarpCorners corners;
      for (int k = 0; k < 4; ++k) corners[k] = field.at(mx + (k & 1), my + (k >> 1));
      MacroblockIntermediate intermediate;
      MacroblockPrediction prediction;
      predict_warp_macroblock(original, mx, my, corners, &intermediate);
      finish_prediction(intermediate, nullptr, &prediction);
      for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 16; ++x) {
          const double d = prediction.y[16 * y + x] - source.y[static_cast<size_t>(16 * my + y) * w + 16 * mx + x];
          squared += d * d;
          ++samples;
        }
      }
    }
  }
  const double prediction_psnr = 10 * std::log10(255.0 * 255.0 * samples / squared);
  EXPECT_GT(prediction_psnr, 40.0);

  BFrameParams params;
  params.qindex = suggested_b_qindex(q);
  params.deblocking = params.cdef = false;  // the predictions alone
  BFrameStats warped_stats, plain_stats;
  ImageYCbCr420 warped_reconstruction, plain_reconstruction;
  const std::vector<uint8_t> warped = encode_b_frame(source, reference, nullptr,
                                                     candidate_hints(candidates, {}, &field, nullptr), params,
                                                     &warped_reconstruction, &warped_stats);
  params.warp = false;
  const std::vector<uint8_t> plain = encode_b_frame(source, reference, nullptr,
                                                    candidate_hints(candidates, {}, &field, nullptr), params,
                                                    &plain_reconstruction, &plain_stats);
  EXPECT_EQ(plain_stats.mb_warp, 0);
  EXPECT_GE(warped_stats.mb_warp, 56);  // of 64
  EXPECT_LT(warped.size() * 3, plain.size() * 2) << warped.size() << " vs translational " << plain.size();
  auto psnr_y = [&](const ImageYCbCr420& image) {
    double sum = 0;
    for (size_t i = 0; i < image.y.size(); ++i) sum += std::pow(image.y[i] - source.y[i], 2);
    return 10 * std::log10(255.0 * 255.0 * image.y.size() / sum);
  };
  EXPECT_GT(psnr_y(warped_reconstruction), psnr_y(plain_reconstruction) - 0.3);
  ImageYCbCr420 decoded;
  std::vector<MacroblockMode> modes;
  std::vector<uint8_t> warped_map;
  ASSERT_TRUE(decode_b_frame(warped, w, h, reference, nullptr, &decoded, &modes, nullptr, &warped_map).ok());
  EXPECT_EQ(decoded.y, warped_reconstruction.y);
  // The decoder reports the warped macroblocks the encoder chose (skipped ones aside).
  ASSERT_EQ(warped_map.size(), modes.size());
  const auto reported = std::count(warped_map.begin(), warped_map.end(), 1);
  EXPECT_LE(reported, warped_stats.mb_warp);
  EXPECT_GE(reported, warped_stats.mb_warp - warped_stats.mb_skipped);
  EXPECT_GT(reported, 0);
  for (size_t m = 0; m < modes.size(); ++m) {
    if (warped_map[m]) EXPECT_TRUE(modes[m] != MacroblockMode::kIntra && modes[m] != MacroblockMode::kSkipped);
  }
  ASSERT_TRUE(decode_b_frame(plain, w, h, reference, nullptr, &decoded, nullptr, nullptr, &warped_map).ok());
  EXPECT_EQ(std::count(warped_map.begin(), warped_map.end(), 1), 0);  // translations only
}

TEST(WarpBFrame, DamagedWarpPayloadsAreRejectedOrDecodeSafely) {
  const int w = 64, h = 48;
  const ImageYCbCr420 source =
      sample_image(w, h, [](double x, double y, double* u, double* v) { kPlane.apply(x, y, u, v); });
  const ImageYCbCr420 ref0 = sample_image(w, h, [](double x, double y, double* u, double* v) {
    *u = x;
    *v = y;
  });
  const ImageYCbCr420 ref1 = sample_image(w, h, [](double x, double y, double* u, double* v) {
    *u = x + 1;
    *v = y;
  });
  const WarpField field0 = exact_nodes(w, h, kPlane), field1 = test_field(w, h, 1, 0, 4);
  BFrameParams params;
  params.qindex = 96;
  BFrameStats stats;
  const std::vector<uint8_t> valid =
      encode_b_frame(source, ref0, &ref1, candidate_hints({}, {}, &field0, &field1), params, nullptr, &stats);
  ASSERT_GT(stats.mb_warp, 0);
  ASSERT_GT(stats.warp_nodes_coded, 0);
  ImageYCbCr420 out;
  ASSERT_TRUE(decode_b_frame(valid, w, h, ref0, &ref1, &out).ok());
  // A payload may leave out up to kImplicitZeroBytes final zeros (docs/codec.md 6.1), so a
  // cut that short may decode (to some picture); any longer cut is reported.
  for (size_t length = 0; length + kImplicitZeroBytes < valid.size(); ++length) {
    const std::vector<uint8_t> cut(valid.begin(), valid.begin() + static_cast<ptrdiff_t>(length));
    EXPECT_FALSE(decode_b_frame(cut, w, h, ref0, &ref1, &out).ok()) << length << " of " << valid.size();
  }
  // A warp mask naming a missing reference (header byte 3, bits 6-7).
  const std::vector<uint8_t> one_ref =
      encode_b_frame(source, ref0, nullptr, candidate_hints({}, {}, &field0, nullptr), params, nullptr, nullptr);
  BFrameHeader header;
  ASSERT_TRUE(parse_b_frame_header(one_ref, &header).ok());
  ASSERT_EQ(header.warp_mask, 1);
  std::vector<uint8_t> changed = one_ref;
  changed[kBFrameReferencesByte] |= 0xC0;
  EXPECT_EQ(decode_b_frame(changed, w, h, ref0, nullptr, &out).code(), ErrorCode::kCorruptData);

  std::mt19937 rng(9);
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<uint8_t> bytes = valid;
    for (int f = 0; f <= trial % 3; ++f) {
      bytes[kBFrameHeaderBytes + rng() % (bytes.size() - kBFrameHeaderBytes)] ^=
          static_cast<uint8_t>(1u << (rng() % 8));
    }
    if (decode_b_frame(bytes, w, h, ref0, &ref1, &out).ok()) {
      ++accepted;
      EXPECT_EQ(out.y.size(), static_cast<size_t>(w * h));
    }
  }
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<uint8_t> bytes(static_cast<size_t>(kBFrameHeaderBytes + rng() % 300));
    for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
    BFrameHeader random_header;  // bare references (border 0), both warped
    random_header.qindex = static_cast<int>(rng() % 256);
    random_header.loop_filters = static_cast<int>(rng() & kLoopFilterDeblocking);
    random_header.filter = static_cast<InterpolationFilter>(rng() % kInterpolationFilterCount);
    random_header.reference_count = 2;
    random_header.warp_mask = 3;
    const auto header_bytes = serialize_b_frame_header(random_header);
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

}  // namespace
}  // namespace svc::codec
