// SPDX-License-Identifier: BSD-2-Clause
// predict_depth's arithmetic is specified operation by operation; the build's
// -ffp-contract=off keeps a fused multiply-add from changing its bits.
#include "codec/common/depth.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace svc::codec {

namespace {

// LOCO-I's median edge detector.
int32_t med(int32_t a, int32_t b, int32_t c) {
  if (c >= std::max(a, b)) return std::min(a, b);
  if (c <= std::min(a, b)) return std::max(a, b);
  return a + b - c;
}

int32_t clamp_code(int64_t v) { return static_cast<int32_t>(std::clamp<int64_t>(v, 1, 65535)); }

uint16_t saturate(int32_t v) { return static_cast<uint16_t>(std::min(v, 65535)); }

// Rotation rows and translation of a view matrix (column-major: element (i, j) at j*4+i).
struct Rigid {
  double r[3][3];
  double t[3];
};

Rigid rigid_of(const Camera& camera) {
  Rigid m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.r[i][j] = camera.world_to_camera[static_cast<size_t>(j * 4 + i)];
    m.t[i] = camera.world_to_camera[static_cast<size_t>(12 + i)];
  }
  return m;
}

// Reference eye space to target eye space: p_t = A p_r + c, with A = R_t R_r^T and
// c = t_t - A t_r (docs/codec.md 7.3).
struct EyeToEye {
  double a[3][3];
  double c[3];
};

EyeToEye eye_to_eye(const Camera& reference, const Camera& target) {
  const Rigid r = rigid_of(reference), t = rigid_of(target);
  EyeToEye m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      m.a[i][j] = ((t.r[i][0] * r.r[j][0]) + (t.r[i][1] * r.r[j][1])) + (t.r[i][2] * r.r[j][2]);
  }
  for (int i = 0; i < 3; ++i)
    m.c[i] = t.t[i] - (((m.a[i][0] * r.t[0]) + (m.a[i][1] * r.t[1])) + (m.a[i][2] * r.t[2]));
  return m;
}

void splat_face(const DepthReference& reference, const Camera& target, int width, int height,
                DepthPrediction* out) {
  const Frustum& rf = reference.camera->frustum;
  const Frustum& tf = target.frustum;
  const EyeToEye m = eye_to_eye(*reference.camera, target);
  // Per column and row: the direction terms A (sx, sy, -n) of a pixel centre's ray.
  std::vector<std::array<double, 3>> column(static_cast<size_t>(width)), row(static_cast<size_t>(height));
  for (int x = 0; x < width; ++x) {
    const double sx = rf.left + ((x + 0.5) * (rf.right - rf.left)) / width;
    for (int i = 0; i < 3; ++i) column[static_cast<size_t>(x)][static_cast<size_t>(i)] = m.a[i][0] * sx;
  }
  for (int y = 0; y < height; ++y) {
    const double sy = rf.top - ((y + 0.5) * (rf.top - rf.bottom)) / height;
    for (int i = 0; i < 3; ++i) row[static_cast<size_t>(y)][static_cast<size_t>(i)] = m.a[i][1] * sy;
  }
  double depth_term[3];
  for (int i = 0; i < 3; ++i) depth_term[i] = m.a[i][2] * (-rf.near_plane);
  const double x_scale = width / (tf.right - tf.left), y_scale = height / (tf.top - tf.bottom);
  for (int y = 0; y < height; ++y) {
    const uint16_t* codes = reference.codes + static_cast<size_t>(y) * width;
    const auto& ry = row[static_cast<size_t>(y)];
    for (int x = 0; x < width; ++x) {
      if (codes[x] == 0) continue;
      const double k = kInverseDepthScale / codes[x];
      const auto& cx = column[static_cast<size_t>(x)];
      double p[3];
      for (int i = 0; i < 3; ++i)
        p[i] = (((cx[static_cast<size_t>(i)] + ry[static_cast<size_t>(i)]) + depth_term[i]) * k) + m.c[i];
      const double z = -p[2];
      if (!(z > 0)) continue;
      const double q = tf.near_plane / z;
      const double u = ((p[0] * q) - tf.left) * x_scale;
      const double v = (tf.top - (p[1] * q)) * y_scale;
      if (!(u >= 0 && u < width && v >= 0 && v < height)) continue;
      const size_t at = static_cast<size_t>(static_cast<int>(v)) * width + static_cast<size_t>(static_cast<int>(u));
      const double code = std::floor((kInverseDepthScale * tf.near_plane) / z + 0.5);
      const auto c = static_cast<uint16_t>(std::clamp(code, 1.0, 65535.0));
      if (out->hints[at] != DepthHint::kGeometry || c > out->predicted[at]) {
        out->predicted[at] = c;
        out->hints[at] = DepthHint::kGeometry;
      }
    }
  }
}

}  // namespace

uint16_t inverse_depth_code(float eye_z, double near_plane) {
  if (!(eye_z > 0) || !std::isfinite(eye_z)) return 0;
  const double code = std::floor((kInverseDepthScale * near_plane) / eye_z + 0.5);
  return static_cast<uint16_t>(std::clamp(code, 1.0, 65535.0));
}

float eye_depth_of_code(uint16_t code, double near_plane) {
  if (code == 0) return std::numeric_limits<float>::infinity();
  return static_cast<float>((kInverseDepthScale * near_plane) / code);
}

void predict_depth(std::span<const DepthReference> references, const Camera& target, int width, int height,
                   DepthPrediction* out) {
  const size_t pixels = static_cast<size_t>(width) * height;
  out->predicted.assign(pixels, 0);
  out->hints.assign(pixels, DepthHint::kNone);
  for (const DepthReference& reference : references) splat_face(reference, target, width, height, out);
  if (references.empty()) return;
  const uint16_t* own = references.front().codes;
  for (size_t i = 0; i < pixels; ++i) {
    if (out->hints[i] == DepthHint::kNone && own[i] == 0) out->hints[i] = DepthHint::kBackground;
  }
}

DepthModel::DepthModel(int width, int height, int max_error, const DepthPrediction* prediction)
    : width_(width),
      height_(height),
      step_(2 * max_error + 1),
      prediction_(prediction),
      codes_(static_cast<size_t>(width) * height, 0),
      intra_error_(codes_.size(), 0),
      inter_error_(codes_.size(), 0) {}

int DepthModel::background_context(int x, int y) const {
  const int left = x > 0 && codes_[index(x - 1, y)] == 0;
  const int top = y > 0 && codes_[index(x, y - 1)] == 0;
  const int hint = prediction_ ? static_cast<int>(prediction_->hints[index(x, y)]) : 0;
  return left + 2 * top + 4 * hint;
}

int32_t DepthModel::intra_value(int x, int y) const {
  const bool has_a = geometry(x - 1, y), has_b = geometry(x, y - 1), has_c = geometry(x - 1, y - 1);
  const int32_t a = has_a ? codes_[index(x - 1, y)] : 0;
  const int32_t b = has_b ? codes_[index(x, y - 1)] : 0;
  if (has_a && has_b && has_c) return clamp_code(med(a, b, codes_[index(x - 1, y - 1)]));
  if (has_a && has_b) return (a + b + 1) >> 1;
  if (has_a) return a;
  if (has_b) return b;
  if (has_c) return codes_[index(x - 1, y - 1)];
  return std::max<int32_t>(last_geometry_, 1);
}

// The reprojected code corrected by its neighbours' errors against it.
bool DepthModel::inter_value(int x, int y, int32_t* value) const {
  if (prediction_ == nullptr || prediction_->hints[index(x, y)] != DepthHint::kGeometry) return false;
  const auto difference = [&](int nx, int ny, int32_t* d) {
    if (!geometry(nx, ny) || prediction_->hints[index(nx, ny)] != DepthHint::kGeometry) return false;
    *d = int32_t{codes_[index(nx, ny)]} - prediction_->predicted[index(nx, ny)];
    return true;
  };
  int32_t ea = 0, eb = 0, ec = 0;
  const bool has_a = difference(x - 1, y, &ea), has_b = difference(x, y - 1, &eb),
             has_c = difference(x - 1, y - 1, &ec);
  int32_t correction = 0;
  if (has_a && has_b && has_c) {
    correction = med(ea, eb, ec);
  } else if (has_a && has_b) {
    correction = (ea + eb) >> 1;
  } else if (has_a) {
    correction = ea;
  } else if (has_b) {
    correction = eb;
  }
  *value = clamp_code(int64_t{prediction_->predicted[index(x, y)]} + correction);
  return true;
}

DepthPixelPrediction DepthModel::predict(int x, int y) const {
  DepthPixelPrediction p;
  p.intra_value = intra_value(x, y);
  p.has_inter = inter_value(x, y, &p.inter_value);
  int32_t intra_score = 0, inter_score = 0, activity = 0;
  for (const auto& [nx, ny] : {std::pair{x - 1, y}, std::pair{x, y - 1}}) {
    if (!geometry(nx, ny)) continue;
    const size_t at = index(nx, ny);
    intra_score += intra_error_[at];
    inter_score += inter_error_[at];
    activity += std::min(intra_error_[at], inter_error_[at]);
  }
  p.inter = p.has_inter && inter_score <= intra_score;
  p.value = p.inter ? p.inter_value : p.intra_value;
  p.activity = std::min(static_cast<int>(std::bit_width(static_cast<uint32_t>(activity / step_))),
                        DepthContexts::kActivityClasses - 1);
  return p;
}

void DepthModel::record(int x, int y, uint16_t code, const DepthPixelPrediction& p) {
  const size_t at = index(x, y);
  codes_[at] = code;
  if (code == 0) return;
  last_geometry_ = code;
  intra_error_[at] = saturate(std::abs(int32_t{code} - p.intra_value));
  inter_error_[at] = p.has_inter ? saturate(std::abs(int32_t{code} - p.inter_value)) : uint16_t{65535};
}

uint16_t DepthModel::reconstruct(const DepthPixelPrediction& p, int32_t q) const {
  return static_cast<uint16_t>(clamp_code(int64_t{p.value} + int64_t{q} * step_));
}

}  // namespace svc::codec
