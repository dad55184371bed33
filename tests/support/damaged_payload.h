// SPDX-License-Identifier: BSD-2-Clause
// Decoding of a damaged B-face payload, as the corruption tests check it: decoded twice,
// it gives the same status both times, and either a whole frame of the right size with
// the same pixels both times or kCorruptData with a message.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <string>

#include "codec/decoder/bframe_decoder.h"
#include "svc/types.h"

namespace svc::testing {

// Returns whether the payload decoded; records a failure for anything else.
inline bool decodes_whole_or_refused(std::span<const uint8_t> bytes, int width, int height,
                                     const ImageYCbCr420& ref0, const ImageYCbCr420* ref1,
                                     const std::string& what) {
  ImageYCbCr420 first, second;
  const Status a = codec::decode_b_frame(bytes, width, height, ref0, ref1, &first);
  const Status b = codec::decode_b_frame(bytes, width, height, ref0, ref1, &second);
  EXPECT_EQ(a.code(), b.code()) << what;
  if (!a.ok()) {
    EXPECT_EQ(a.code(), ErrorCode::kCorruptData) << what << ": " << a.message();
    EXPECT_FALSE(a.message().empty()) << what;
    return false;
  }
  EXPECT_EQ(first.y.size(), static_cast<size_t>(width) * height) << what;
  EXPECT_EQ(first.cb.size(), static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2)) << what;
  EXPECT_TRUE(first.y == second.y && first.cb == second.cb && first.cr == second.cr) << what;
  return true;
}

}  // namespace svc::testing
