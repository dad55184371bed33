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

// round(kInverseDepthScale n / z) in 1..65535, for finite z > 0 (docs/codec.md 8.1, 8.3).
uint16_t code_of_depth(double z, double near_plane) {
  const double code = std::floor((kInverseDepthScale * near_plane) / z + 0.5);
  return static_cast<uint16_t>(std::clamp(code, 1.0, 65535.0));
}

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
// c = t_t - A t_r (docs/codec.md 8.3).
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
      const uint16_t c = code_of_depth(z, tf.near_plane);
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
  return code_of_depth(eye_z, near_plane);
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
      stride_(static_cast<size_t>(width) + 2),
      codes_(stride_ * (static_cast<size_t>(height) + 1), 0),
      intra_error_(codes_.size(), 0),
      inter_error_(codes_.size(), 0),
      residual_sign_(codes_.size(), 0) {}

void DepthModel::copy_codes(uint16_t* out) const {
  for (int y = 0; y < height_; ++y) {
    std::copy_n(codes_.begin() + static_cast<std::ptrdiff_t>(index(0, y)), width_,
                out + static_cast<size_t>(y) * static_cast<size_t>(width_));
  }
}

}  // namespace svc::codec
