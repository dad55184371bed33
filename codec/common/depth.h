// SPDX-License-Identifier: BSD-2-Clause
// Depth planes (docs/codec.md section 8): the inverse-depth codes a face's depth is coded
// as, the prediction of a B-face's depth from its reference cubes reprojected, and the
// per-pixel predictor and contexts that the depth encoder and decoder share.
// Threading: plain functions and data; a DepthModel is single-threaded.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "codec/common/adaptive_bit.h"
#include "svc/types.h"

namespace svc::codec {

// The depth syntax the encoder writes, and the first a decoder reads: format 1.0's
// (docs/codec.md 1.1).
inline constexpr uint8_t kDepthSyntaxVersion = 1;
inline constexpr uint8_t kDepthSyntaxFirst = 1;
inline constexpr size_t kDepthHeaderBytes = 3;  // version, flags, maximum error
inline constexpr uint8_t kDepthFlagInter = 1;   // predicted from the reference cubes
inline constexpr int kMaxDepthError = 255;      // in inverse-depth code units
// Code c of eye depth z on a face with near plane n: c = round(kInverseDepthScale n / z),
// clamped to 1..65535; 0 marks a pixel without geometry.
inline constexpr double kInverseDepthScale = 65535.0;

// The code of eye-space depth z (positive, along the view axis) on a face whose near
// plane is `near_plane`; 0 for a pixel without geometry (z infinite, NaN or <= 0).
uint16_t inverse_depth_code(float eye_z, double near_plane);
// Eye-space depth of a code: kInverseDepthScale n / c, +infinity for 0.
float eye_depth_of_code(uint16_t code, double near_plane);

// A reference face's reconstructed depth codes (width x height, row 0 at the top) and its
// camera.
struct DepthReference {
  const uint16_t* codes = nullptr;
  const Camera* camera = nullptr;
};

// What the reference cubes say about each pixel of a B-face.
enum class DepthHint : uint8_t {
  kNone = 0,        // no reference point lands here, and no background either
  kBackground = 1,  // the first reference's own face has no geometry at this pixel
  kGeometry = 2,    // `predicted` holds the nearest reprojected code
};

struct DepthPrediction {
  std::vector<uint16_t> predicted;  // width * height
  std::vector<DepthHint> hints;     // width * height
};

// Reprojects every geometry pixel of `references` (the first reference's own face first)
// into `target`'s view and keeps the nearest at each pixel (docs/codec.md 8.3). Exact
// IEEE double arithmetic in a fixed order: the same codes on every machine.
void predict_depth(std::span<const DepthReference> references, const Camera& target, int width, int height,
                   DepthPrediction* out);

// The contexts of one depth plane's coding (docs/codec.md 8.4).
struct DepthContexts {
  static constexpr int kActivityClasses = 12;
  static constexpr int kMagnitudeBits = 16;
  // Indexed by DepthModel::background_context: left (2) x above (2) x DepthHint (3).
  std::array<AdaptiveBit, 2 * 2 * 3> background{};
  // Indexed [inter][activity][residuals left and above that are not 0, 0..2].
  std::array<std::array<std::array<AdaptiveBit, 3>, kActivityClasses>, 2> zero{};
  // Indexed [inter][signs of the residuals left and above, 0..8].
  std::array<std::array<AdaptiveBit, 9>, 2> sign{};
  // Indexed [inter][activity][unary position of the magnitude's bit width].
  std::array<std::array<std::array<AdaptiveBit, kMagnitudeBits>, kActivityClasses>, 2> magnitude{};
};

// The prediction of one pixel and the contexts its value is coded with.
struct DepthPixelPrediction {
  int32_t value = 0;  // 1..65535: inter_value when `inter`, else intra_value
  int inter = 0;      // predicted from the reprojected references
  int activity = 0;   // 0..kActivityClasses-1
  int signs = 0;      // the residuals' signs left and above: 3 (left + 1) + (above + 1)
  int moved = 0;      // how many of those residuals are not 0
  int32_t intra_value = 0;
  int32_t inter_value = 0;
  bool has_inter = false;  // the pixel has a reprojected code
};

// The causal state of a plane being coded: reconstructed codes and each predictor's
// errors so far. The encoder and decoder walk pixels in raster order through it.
class DepthModel {
 public:
  // `prediction` is null for an I-face; it must outlive the model.
  DepthModel(int width, int height, int max_error, const DepthPrediction* prediction);

  // Context index of pixel (x, y)'s background flag.
  int background_context(int x, int y) const;
  DepthPixelPrediction predict(int x, int y) const;
  // Records the reconstructed code of (x, y) (0: background) after its prediction `p`.
  void record(int x, int y, uint16_t code, const DepthPixelPrediction& p);

  int step() const { return step_; }
  // The reconstruction of quantized residual q (docs/codec.md 8.4).
  uint16_t reconstruct(const DepthPixelPrediction& p, int32_t q) const;
  // The reconstructed codes, width * height.
  void copy_codes(uint16_t* out) const;

 private:
  int32_t intra_value(int x, int y) const;
  bool inter_value(int x, int y, int32_t* value) const;
  // The model's planes have a border of pixels without geometry: one row above, one
  // column on each side.
  bool geometry(int x, int y) const { return codes_[index(x, y)] != 0; }
  size_t index(int x, int y) const { return static_cast<size_t>(y + 1) * stride_ + static_cast<size_t>(x + 1); }
  size_t pixel(int x, int y) const { return static_cast<size_t>(y) * static_cast<size_t>(width_) + x; }

  int width_, height_, step_;
  const DepthPrediction* prediction_;
  size_t stride_;
  std::vector<uint16_t> codes_;
  // Errors of the two predictions at each pixel with geometry; 0 elsewhere.
  std::vector<uint16_t> intra_error_, inter_error_;
  // The sign of each pixel's residual (-1, 0, 1); 0 without geometry.
  std::vector<int8_t> residual_sign_;
  uint16_t last_geometry_ = 0;
};

namespace depth_internal {

// LOCO-I's median edge detector.
inline int32_t med(int32_t a, int32_t b, int32_t c) {
  if (c >= std::max(a, b)) return std::min(a, b);
  if (c <= std::min(a, b)) return std::max(a, b);
  return a + b - c;
}
inline int32_t clamp_code(int64_t v) { return static_cast<int32_t>(std::clamp<int64_t>(v, 1, 65535)); }
inline uint16_t saturate(int32_t v) { return static_cast<uint16_t>(std::min(v, 65535)); }

}  // namespace depth_internal

// Inline: the decoder calls these once a pixel.
inline int DepthModel::background_context(int x, int y) const {
  const int left = x > 0 && codes_[index(x - 1, y)] == 0;
  const int top = y > 0 && codes_[index(x, y - 1)] == 0;
  const int hint = prediction_ ? static_cast<int>(prediction_->hints[pixel(x, y)]) : 0;
  return left + 2 * top + 4 * hint;
}

inline int32_t DepthModel::intra_value(int x, int y) const {
  const bool has_a = geometry(x - 1, y), has_b = geometry(x, y - 1), has_c = geometry(x - 1, y - 1);
  const int32_t a = codes_[index(x - 1, y)], b = codes_[index(x, y - 1)], c = codes_[index(x - 1, y - 1)];
  if (has_a && has_b && has_c) return depth_internal::clamp_code(depth_internal::med(a, b, c));
  if (has_a && has_b) return (a + b + 1) >> 1;
  if (has_a) return a;
  if (has_b) return b;
  if (has_c) return c;
  return std::max<int32_t>(last_geometry_, 1);
}

// The reprojected code corrected by its neighbours' errors against it.
inline bool DepthModel::inter_value(int x, int y, int32_t* value) const {
  if (prediction_ == nullptr || prediction_->hints[pixel(x, y)] != DepthHint::kGeometry) return false;
  const auto difference = [&](int nx, int ny, int32_t* d) {
    if (!geometry(nx, ny) || prediction_->hints[pixel(nx, ny)] != DepthHint::kGeometry) return false;
    *d = int32_t{codes_[index(nx, ny)]} - prediction_->predicted[pixel(nx, ny)];
    return true;
  };
  int32_t ea = 0, eb = 0, ec = 0;
  const bool has_a = difference(x - 1, y, &ea), has_b = difference(x, y - 1, &eb),
             has_c = difference(x - 1, y - 1, &ec);
  int32_t correction = 0;
  if (has_a && has_b && has_c) {
    correction = depth_internal::med(ea, eb, ec);
  } else if (has_a && has_b) {
    correction = (ea + eb) >> 1;
  } else if (has_a) {
    correction = ea;
  } else if (has_b) {
    correction = eb;
  }
  *value = depth_internal::clamp_code(int64_t{prediction_->predicted[pixel(x, y)]} + correction);
  return true;
}

inline DepthPixelPrediction DepthModel::predict(int x, int y) const {
  DepthPixelPrediction p;
  p.intra_value = intra_value(x, y);
  p.has_inter = inter_value(x, y, &p.inter_value);
  // Pixels without geometry (the border included) hold errors 0, so they add nothing.
  const size_t a = index(x - 1, y), b = index(x, y - 1), c = b - 1, d = b + 1;
  const int32_t intra_score = int32_t{intra_error_[a]} + intra_error_[b];
  const int32_t inter_score = int32_t{inter_error_[a]} + inter_error_[b];
  // The errors above-left and above-right foretell an edge coming in.
  int32_t activity = 0;
  for (size_t at : {a, b, c, d}) activity += std::min(intra_error_[at], inter_error_[at]);
  p.inter = p.has_inter && inter_score < intra_score;
  p.value = p.inter ? p.inter_value : p.intra_value;
  p.signs = 3 * (residual_sign_[a] + 1) + (residual_sign_[b] + 1);
  p.moved = (residual_sign_[a] != 0) + (residual_sign_[b] != 0);
  p.activity = std::min(static_cast<int>(std::bit_width(static_cast<uint32_t>(activity / step_))),
                        DepthContexts::kActivityClasses - 1);
  return p;
}

inline void DepthModel::record(int x, int y, uint16_t code, const DepthPixelPrediction& p) {
  const size_t at = index(x, y);
  codes_[at] = code;
  if (code == 0) return;
  last_geometry_ = code;
  residual_sign_[at] = static_cast<int8_t>((code > p.value) - (code < p.value));
  intra_error_[at] = depth_internal::saturate(std::abs(int32_t{code} - p.intra_value));
  inter_error_[at] = p.has_inter ? depth_internal::saturate(std::abs(int32_t{code} - p.inter_value))
                                 : uint16_t{65535};
}

inline uint16_t DepthModel::reconstruct(const DepthPixelPrediction& p, int32_t q) const {
  return static_cast<uint16_t>(depth_internal::clamp_code(int64_t{p.value} + int64_t{q} * step_));
}

}  // namespace svc::codec
