// SPDX-License-Identifier: BSD-2-Clause
// The encoder's self-check: a coded face must decode to the encoder's reconstruction,
// else the encode stops with an internal error instead of writing the file.
#include <gtest/gtest.h>

#include <vector>

#include "codec/common/intra_frame.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/intra_encoder.h"
#include "encoder/face_coding.h"

namespace svc {
namespace {

ImageYCbCr420 gradient(int width, int height) {
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  image.y.resize(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) image.y[static_cast<size_t>(y) * width + x] = static_cast<uint8_t>(3 * x + y);
  }
  const size_t chroma = static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2);
  image.cb.assign(chroma, 110);
  image.cr.assign(chroma, 150);
  return image;
}

TEST(EncoderSelfCheck, AcceptsAPayloadThatDecodesToTheReconstruction) {
  ImageYCbCr420 reconstruction;
  const std::vector<uint8_t> payload = codec::encode_intra_frame(gradient(48, 32), {80}, &reconstruction);
  EXPECT_TRUE(check_intra_payload(payload, reconstruction, "cell (1,0,2) face px").ok());
}

TEST(EncoderSelfCheck, OtherPixelsAreAnInternalErrorNamingTheFace) {
  ImageYCbCr420 reconstruction;
  const std::vector<uint8_t> payload = codec::encode_intra_frame(gradient(48, 32), {80}, &reconstruction);
  reconstruction.cr[5] ^= 1;
  const Status status = check_intra_payload(payload, reconstruction, "cell (1,0,2) face px");
  EXPECT_EQ(status.code(), ErrorCode::kInternal);
  EXPECT_NE(status.message().find("cell (1,0,2) face px"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("other pixels"), std::string::npos) << status.message();
}

TEST(EncoderSelfCheck, APayloadTheDecoderRejectsIsAnInternalErrorWithTheDecodersReason) {
  ImageYCbCr420 reconstruction;
  std::vector<uint8_t> payload = codec::encode_intra_frame(gradient(48, 32), {80}, &reconstruction);
  payload.resize(payload.size() / 2);
  const Status status = check_intra_payload(payload, reconstruction, "cell (0,0,0) face nz");
  EXPECT_EQ(status.code(), ErrorCode::kInternal);
  EXPECT_NE(status.message().find("cell (0,0,0) face nz"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("truncated"), std::string::npos) << status.message();
}

}  // namespace
}  // namespace svc
