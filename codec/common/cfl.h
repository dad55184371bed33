// SPDX-License-Identifier: BSD-2-Clause
// Chroma from luma (CfL), a chroma intra mode: an 8x8 chroma block predicted as its DC
// prediction plus alpha times the variation of the co-located reconstructed luma
// (averaged 2x2 to chroma resolution, less its mean). docs/codec.md 3.3 defines the
// prediction and the syntax: a CfL flag before the regular mode of a Cb block, then Cb's
// alpha; a Cr block of a CfL Cb block codes its own alpha. The syntax is read by
// codec/decoder/intra_syntax_reader.h and written by codec/encoder/intra_syntax_writer.h.
//
// Threading: pure functions; CflContexts is plain mutable data owned by one coder.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "codec/common/adaptive_bit.h"
#include "codec/common/intra_prediction.h"

namespace svc::codec {

// The chroma mode after the 35 regular ones.
inline constexpr int kCflMode = kIntraModes;
// Alpha is in 1/8 and lies in -kCflMaxAlpha..kCflMaxAlpha (-2..2).
inline constexpr int kCflMaxAlpha = 16;

// The CoefficientFrame::block_modes byte of a CfL chroma block carries its alpha:
// kCflMode + kCflMaxAlpha + alpha (35..67). Regular modes are 0..34.
inline constexpr uint8_t cfl_mode_byte(int alpha) { return static_cast<uint8_t>(kCflMode + kCflMaxAlpha + alpha); }
inline constexpr bool is_cfl_mode_byte(int byte) { return byte >= kCflMode && byte <= kCflMode + 2 * kCflMaxAlpha; }
inline constexpr int cfl_alpha_of_mode_byte(int byte) { return byte - kCflMode - kCflMaxAlpha; }

enum class ChromaPlane { kCb, kCr };

// A chroma block's mode: a regular one (0..34), or kCflMode with its alpha.
struct ChromaMode {
  int mode = kDcMode;
  int alpha = 0;
  bool cfl() const { return mode == kCflMode; }
  uint8_t mode_byte() const { return cfl() ? cfl_mode_byte(alpha) : static_cast<uint8_t>(mode); }
};

struct CflContexts {
  std::array<AdaptiveBit, 3> flag{};                                     // by cfl_context
  AdaptiveBit cr_nonzero;                                                // Cr's alpha is not 0
  std::array<AdaptiveBit, 3> sign{};                                     // Cb; Cr after Cb > 0; Cr after Cb < 0
  std::array<std::array<AdaptiveBit, kCflMaxAlpha - 1>, 2> magnitude{};  // per plane, by bin
};

// Calls f on every context, in member order (docs/codec.md 6.1).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, CflContexts>
void for_each_context(Set& s, F&& f) {
  for_each_bit(s.flag, f);
  for_each_bit(s.cr_nonzero, f);
  for_each_bit(s.sign, f);
  for_each_bit(s.magnitude, f);
}

// The contexts of an alpha's sign (Cb; Cr after Cb > 0; Cr after Cb < 0) and of its
// magnitude bins (per plane).
inline size_t cfl_sign_context(ChromaPlane plane, int cb_alpha) {
  if (plane == ChromaPlane::kCb) return 0;
  return cb_alpha < 0 ? 2 : 1;
}
inline size_t cfl_plane_index(ChromaPlane plane) { return plane == ChromaPlane::kCb ? 0 : 1; }

// The 64 luma AC values of the 8x8 chroma block at chroma sample (x0, y0), from the
// reconstructed luma plane (stride samples per row, holding at least (2 x0 + 16) x
// (2 y0 + 16) samples).
void cfl_luma_ac(const uint8_t* luma, ptrdiff_t stride, int x0, int y0, int16_t* ac);
// The DC prediction of an 8x8 block from its edge (docs/codec.md 5.2, mode 1).
int dc_prediction_8x8(const uint8_t* edge);
// The CfL prediction: clip(dc + ((alpha * ac + 16) >> 5), 0, 255).
void predict_cfl(const int16_t* ac, int dc, int alpha, uint8_t* out);

}  // namespace svc::codec
