// SPDX-License-Identifier: BSD-2-Clause
// Depth planes (docs/codec.md section 7): the inverse-depth codes a face's depth is coded
// as, the prediction of a B-face's depth from its reference cubes reprojected, and the
// per-pixel predictor and contexts that the depth encoder and decoder share.
// Threading: plain functions and data; a DepthModel is single-threaded.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/common/adaptive_bit.h"
#include "svc/types.h"

namespace svc::codec {

inline constexpr uint8_t kDepthSyntaxVersion = 1;
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
// into `target`'s view and keeps the nearest at each pixel (docs/codec.md 7.3). Exact
// IEEE double arithmetic in a fixed order: the same codes on every machine.
void predict_depth(std::span<const DepthReference> references, const Camera& target, int width, int height,
                   DepthPrediction* out);

// The contexts of one depth plane's coding (docs/codec.md 7.4).
struct DepthContexts {
  static constexpr int kActivityClasses = 12;
  static constexpr int kMagnitudeBits = 16;
  std::array<AdaptiveBit, 12> background{};
  // Indexed [inter][activity].
  std::array<std::array<AdaptiveBit, kActivityClasses>, 2> zero{}, sign{};
  std::array<std::array<std::array<AdaptiveBit, kMagnitudeBits>, kActivityClasses>, 2> magnitude{};
};

// The prediction of one pixel and the contexts its value is coded with.
struct DepthPixelPrediction {
  int32_t value = 0;  // 1..65535: inter_value when `inter`, else intra_value
  int inter = 0;      // predicted from the reprojected references
  int activity = 0;   // 0..kActivityClasses-1
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
  // The reconstruction of quantized residual q (docs/codec.md 7.4).
  uint16_t reconstruct(const DepthPixelPrediction& p, int32_t q) const;
  const std::vector<uint16_t>& codes() const { return codes_; }
  std::vector<uint16_t> take_codes() { return std::move(codes_); }

 private:
  int32_t intra_value(int x, int y) const;
  bool inter_value(int x, int y, int32_t* value) const;
  bool geometry(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && codes_[index(x, y)] != 0; }
  size_t index(int x, int y) const { return static_cast<size_t>(y) * static_cast<size_t>(width_) + x; }

  int width_, height_, step_;
  const DepthPrediction* prediction_;
  std::vector<uint16_t> codes_;
  std::vector<uint16_t> intra_error_, inter_error_;
  uint16_t last_geometry_ = 0;
};

}  // namespace svc::codec
