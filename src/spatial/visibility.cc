// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/visibility.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "spatial/camera_terms.h"

namespace svc {
namespace {

bool is_background(float z, const Frustum& frustum) {
  return !(z > 0.0f) || !std::isfinite(z) || static_cast<double>(z) >= frustum.far_plane;
}

// Full-resolution pixel centre of sample i along an axis.
double sample_centre(int i, int step) { return static_cast<double>(step) * i + step / 2 + 0.5; }

// A reference face prepared for projection: the first three rows of its view matrix.
struct ProjectedFace {
  std::array<std::array<double, 4>, 3> rows;
  double p00, p02, p11, p12, near_plane;
  const std::vector<float>* depth;
  const Frustum* frustum;
};

ProjectedFace prepare(const CubeSamples& cube, int f) {
  const Camera& camera = cube.cameras[static_cast<size_t>(f)];
  const Frustum& fr = camera.frustum;
  const ProjectionTerms p = projection_terms(fr);
  ProjectedFace face{{}, p.p00, p.p02, p.p11, p.p12, fr.near_plane, &cube.depth[static_cast<size_t>(f)], &fr};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      face.rows[static_cast<size_t>(r)][static_cast<size_t>(c)] =
          camera.world_to_camera[static_cast<size_t>(c * 4 + r)];
    }
  }
  return face;
}

double dot(const std::array<double, 4>& row, const glm::dvec4& p) {
  return row[0] * p.x + row[1] * p.y + row[2] * p.z + row[3] * p.w;
}

// Whether face `face` of `reference` sees the world point (w = 1) or direction (w = 0).
bool face_sees(const ProjectedFace& face, const CubeSamples& reference, const glm::dvec4& world) {
  // Depth first: most points lie behind most faces of a cube.
  const double depth = -dot(face.rows[2], world);
  if (!(depth > (world.w == 0 ? 0.0 : face.near_plane))) return false;
  // glFrustum projection with clip w = depth.
  const double ndc_x = face.p00 * dot(face.rows[0], world) / depth - face.p02;
  const double ndc_y = face.p11 * dot(face.rows[1], world) / depth - face.p12;
  if (!(ndc_x >= -1.0 && ndc_x < 1.0 && ndc_y > -1.0 && ndc_y <= 1.0)) return false;
  // Landing position in full-resolution pixel-edge coordinates.
  const double u = (ndc_x + 1.0) * 0.5 * reference.face_width;
  const double v = (1.0 - ndc_y) * 0.5 * reference.face_height;
  // The 2x2 samples around the landing point (sample i has its centre at step * i +
  // step / 2 + 0.5).
  const double centre_offset = reference.step / 2 + 0.5;
  const int si = static_cast<int>(std::floor((u - centre_offset) / reference.step));
  const int sj = static_cast<int>(std::floor((v - centre_offset) / reference.step));
  float farthest = 0.0f;
  bool background = false;
  for (int dj = 0; dj <= 1; ++dj) {
    for (int di = 0; di <= 1; ++di) {
      const int x = std::clamp(si + di, 0, reference.width - 1), y = std::clamp(sj + dj, 0, reference.height - 1);
      const float r =
          (*face.depth)[static_cast<size_t>(y) * static_cast<size_t>(reference.width) + static_cast<size_t>(x)];
      if (is_background(r, *face.frustum)) {
        background = true;
      } else {
        farthest = std::max(farthest, r);
      }
    }
  }
  if (world.w == 0) return background;
  return background || depth <= (1.0 + kSampledVisibilityTolerance) * static_cast<double>(farthest);
}

}  // namespace

bool add_face_samples(CubeSamples* cube, Face face, const Camera& camera, int face_width, int face_height,
                      const std::vector<float>& depth, int step) {
  if (face_width <= 0 || face_height <= 0 || step <= 0 ||
      depth.size() != static_cast<size_t>(face_width) * static_cast<size_t>(face_height)) {
    return false;
  }
  const int width = (face_width + step - 1) / step, height = (face_height + step - 1) / step;
  if (cube->width != 0 &&
      (cube->face_width != face_width || cube->face_height != face_height || cube->step != step)) {
    return false;
  }
  cube->step = step;
  cube->face_width = face_width;
  cube->face_height = face_height;
  cube->width = width;
  cube->height = height;
  const int f = static_cast<int>(face);
  cube->cameras[f] = camera;
  std::vector<float>& samples = cube->depth[f];
  samples.resize(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (int j = 0; j < height; ++j) {
    const int y = std::min(step * j + step / 2, face_height - 1);
    for (int i = 0; i < width; ++i) {
      const int x = std::min(step * i + step / 2, face_width - 1);
      samples[static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)] =
          depth[static_cast<size_t>(y) * static_cast<size_t>(face_width) + static_cast<size_t>(x)];
    }
  }
  return true;
}

size_t sample_count(const CubeSamples& cube) {
  return static_cast<size_t>(kFaceCount) * static_cast<size_t>(cube.width) * static_cast<size_t>(cube.height);
}

std::vector<uint64_t> seen_by(const CubeSamples& current, const CubeSamples& reference) {
  const size_t count = sample_count(current);
  if (count == 0 || sample_count(reference) == 0) return {};
  std::vector<uint64_t> seen((count + 63) / 64, 0);
  std::array<ProjectedFace, kFaceCount> faces;
  for (int f = 0; f < kFaceCount; ++f) faces[static_cast<size_t>(f)] = prepare(reference, f);
  size_t k = 0;
  for (int f = 0; f < kFaceCount; ++f) {
    const Camera& camera = current.cameras[static_cast<size_t>(f)];
    const Frustum& cf = camera.frustum;
    const glm::dmat4 to_world = glm::inverse(glm::make_mat4(camera.world_to_camera.data()));
    const std::vector<float>& depth = current.depth[static_cast<size_t>(f)];
    for (int j = 0; j < current.height; ++j) {
      const double y = std::min(sample_centre(j, current.step), current.face_height - 0.5);
      const double b = (cf.bottom + (1.0 - y / current.face_height) * (cf.top - cf.bottom)) / cf.near_plane;
      for (int i = 0; i < current.width; ++i, ++k) {
        const double x = std::min(sample_centre(i, current.step), current.face_width - 0.5);
        const double a = (cf.left + x / current.face_width * (cf.right - cf.left)) / cf.near_plane;
        const float z = depth[static_cast<size_t>(j) * static_cast<size_t>(current.width) + static_cast<size_t>(i)];
        const glm::dvec4 world = is_background(z, cf)
                                     ? to_world * glm::dvec4(a, b, -1.0, 0.0)
                                     : to_world * glm::dvec4(a * z, b * z, -static_cast<double>(z), 1.0);
        for (const ProjectedFace& face : faces) {
          if (face_sees(face, reference, world)) {
            seen[k / 64] |= uint64_t{1} << (k % 64);
            break;
          }
        }
      }
    }
  }
  return seen;
}

size_t count_seen_by_either(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b) {
  size_t n = 0;
  const size_t words = std::min(a.size(), b.size());
  for (size_t w = 0; w < words; ++w) n += static_cast<size_t>(std::popcount(a[w] | b[w]));
  return n;
}

}  // namespace svc
