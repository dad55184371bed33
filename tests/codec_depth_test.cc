// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include "codec/common/depth.h"
#include "codec/decoder/depth_decoder.h"
#include "codec/encoder/depth_encoder.h"

namespace svc::codec {
namespace {

constexpr int kSize = 64;

// A camera at `centre` looking along -z (identity rotation), 90-degree square frustum.
Camera camera_at(double x, double y, double z) {
  Camera camera;
  camera.world_to_camera[12] = -x;
  camera.world_to_camera[13] = -y;
  camera.world_to_camera[14] = -z;
  camera.frustum = {-0.1, 0.1, -0.1, 0.1, 0.1, 100};
  return camera;
}

// Eye depth seen by `camera` (as camera_at builds) of a scene: a wall z = -5 + 0.3 x, a
// box in front of it, and sky above y = 1.2.
std::vector<uint16_t> render_codes(const Camera& camera) {
  const double cx = -camera.world_to_camera[12], cy = -camera.world_to_camera[13];
  std::vector<uint16_t> codes(kSize * kSize);
  for (int j = 0; j < kSize; ++j) {
    for (int i = 0; i < kSize; ++i) {
      const double sx = -1 + (i + 0.5) * 2 / kSize, sy = 1 - (j + 0.5) * 2 / kSize;  // ray (sx, sy, -1)
      double t = (5 - 0.3 * cx) / (1 + 0.3 * sx);
      const double bx = cx + 3 * sx, by = cy + 3 * sy;  // the box's front face at z = -3
      if (bx > -0.5 && bx < 0.4 && by > -0.6 && by < 0.2) t = 3;
      const bool sky = cy + t * sy > 1.2;
      codes[j * kSize + i] = sky ? 0 : inverse_depth_code(static_cast<float>(t), camera.frustum.near_plane);
    }
  }
  return codes;
}

std::vector<uint16_t> decoded(const DepthEncodeResult& coded, std::span<const DepthReference> references,
                              const Camera& target) {
  std::vector<uint16_t> codes(kSize * kSize, 7);
  const Status status = decode_depth(coded.payload, kSize, kSize, references, target, codes.data());
  EXPECT_TRUE(status.ok()) << status.message();
  return codes;
}

int max_error(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b) {
  int worst = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if ((a[i] == 0) != (b[i] == 0)) return std::numeric_limits<int>::max();
    worst = std::max(worst, std::abs(int{a[i]} - int{b[i]}));
  }
  return worst;
}

TEST(DepthCodes, RoundTripThroughEyeDepth) {
  EXPECT_EQ(inverse_depth_code(std::numeric_limits<float>::infinity(), 0.1), 0);
  EXPECT_EQ(inverse_depth_code(std::nanf(""), 0.1), 0);
  EXPECT_EQ(inverse_depth_code(-1.0f, 0.1), 0);
  EXPECT_EQ(inverse_depth_code(0.1f, 0.1), 65535);
  EXPECT_EQ(inverse_depth_code(0.01f, 0.1), 65535);  // nearer than the near plane: clamped
  EXPECT_EQ(inverse_depth_code(1e9f, 0.1), 1);       // geometry never reads as background
  EXPECT_EQ(inverse_depth_code(eye_depth_of_code(1234, 0.1), 0.1), 1234);
  EXPECT_TRUE(std::isinf(eye_depth_of_code(0, 0.1)));
  EXPECT_NEAR(eye_depth_of_code(6553, 0.1), 1.0, 1e-4);
}

TEST(DepthCoding, IntraIsLosslessAtErrorZero) {
  const Camera camera = camera_at(0, 0, 0);
  const std::vector<uint16_t> source = render_codes(camera);
  const DepthEncodeResult coded = encode_depth(source, kSize, kSize, 0, nullptr);
  EXPECT_EQ(coded.reconstructed, source);
  EXPECT_EQ(decoded(coded, {}, camera), source);
  EXPECT_FALSE(depth_payload_is_inter(coded.payload));
  // Smooth surfaces cost far less than the 16 bits a pixel of the raw codes.
  EXPECT_LT(coded.payload.size(), source.size() * 2 / 8);
}

TEST(DepthCoding, LossyKeepsTheBoundAndTheBackground) {
  const Camera camera = camera_at(0, 0, 0);
  std::vector<uint16_t> source = render_codes(camera);
  std::mt19937 random(5);
  for (uint16_t& code : source) {
    if (code != 0) code = static_cast<uint16_t>(std::clamp<int>(code + int(random() % 41) - 20, 1, 65535));
  }
  size_t previous = std::numeric_limits<size_t>::max();
  for (int bound : {0, 1, 4, 16, 255}) {
    const DepthEncodeResult coded = encode_depth(source, kSize, kSize, bound, nullptr);
    EXPECT_EQ(decoded(coded, {}, camera), coded.reconstructed) << bound;
    EXPECT_LE(max_error(coded.reconstructed, source), bound) << bound;
    EXPECT_LT(coded.payload.size(), previous) << bound;
    previous = coded.payload.size();
  }
}

TEST(DepthCoding, InterPredictionFromAMovedCameraIsSmaller) {
  const Camera reference = camera_at(0, 0, 0), target = camera_at(0.3, 0.1, 0);
  const std::vector<uint16_t> reference_codes = render_codes(reference), source = render_codes(target);
  const DepthReference references[] = {{reference_codes.data(), &reference}};
  DepthPrediction prediction;
  predict_depth(references, target, kSize, kSize, &prediction);
  // Most pixels get a reprojected code within a few units of the truth.
  int close = 0;
  for (size_t i = 0; i < source.size(); ++i) {
    close += prediction.hints[i] == DepthHint::kGeometry && std::abs(prediction.predicted[i] - source[i]) <= 8;
  }
  EXPECT_GT(close, kSize * kSize / 2);
  const DepthEncodeResult intra = encode_depth(source, kSize, kSize, 0, nullptr);
  const DepthEncodeResult inter = encode_depth(source, kSize, kSize, 0, &prediction);
  EXPECT_TRUE(depth_payload_is_inter(inter.payload));
  EXPECT_EQ(decoded(inter, references, target), source);
  EXPECT_LT(inter.payload.size(), intra.payload.size());
  // Without its references an inter payload is refused.
  std::vector<uint16_t> codes(kSize * kSize);
  EXPECT_EQ(decode_depth(inter.payload, kSize, kSize, {}, target, codes.data()).code(), ErrorCode::kCorruptData);
}

TEST(DepthCoding, DamagedPayloadsAreRefusedOrDecodeWhole) {
  const Camera camera = camera_at(0, 0, 0);
  const DepthEncodeResult coded = encode_depth(render_codes(camera), kSize, kSize, 0, nullptr);
  std::vector<uint16_t> codes(kSize * kSize);
  // Five bytes short or more: the decoder reads past what kImplicitZeroBytes allows.
  for (size_t size = 0; size + 5 <= coded.payload.size(); size += 7) {
    const Status status =
        decode_depth(std::span(coded.payload).first(size), kSize, kSize, {}, camera, codes.data());
    EXPECT_EQ(status.code(), ErrorCode::kCorruptData) << size;
  }
  std::vector<uint8_t> bad = coded.payload;
  bad[0] = 2;  // a later depth syntax: unsupported, not damaged
  const Status newer = decode_depth(bad, kSize, kSize, {}, camera, codes.data());
  EXPECT_EQ(newer.code(), ErrorCode::kUnsupported);
  EXPECT_NE(newer.message().find(
                "depth: byte 0: syntax version 2 is newer than this build knows (this build reads 1)"),
            std::string::npos)
      << newer.message();
  std::mt19937 random(9);
  for (int trial = 0; trial < 200; ++trial) {
    bad = coded.payload;
    bad[kDepthHeaderBytes + random() % (bad.size() - kDepthHeaderBytes)] ^=
        static_cast<uint8_t>(1 + random() % 255);
    const Status status = decode_depth(bad, kSize, kSize, {}, camera, codes.data());
    if (!status.ok()) EXPECT_EQ(status.code(), ErrorCode::kCorruptData);
  }
}

}  // namespace
}  // namespace svc::codec
