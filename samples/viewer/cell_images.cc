// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/cell_images.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace svc::viewer {

FaceCamera face_camera(const Camera& camera) {
  FaceCamera out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) out.world_to_camera[c][r] = camera.world_to_camera[c * 4 + r];
  }
  out.camera_to_world = glm::inverse(out.world_to_camera);
  out.frustum = camera.frustum;
  return out;
}

glm::dvec2 project_direction(const FaceCamera& camera, int width, int height, const glm::dvec3& d) {
  const glm::dvec3 e = glm::dvec3(camera.world_to_camera * glm::dvec4(d, 0.0));
  if (!(e.z < 0)) {
    constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
    return {kNan, kNan};
  }
  const Frustum& f = camera.frustum;
  // The point where the ray meets the near plane, in the frustum's window.
  const double x = e.x * f.near_plane / -e.z, y = e.y * f.near_plane / -e.z;
  return {(x - f.left) / (f.right - f.left) * width, (f.top - y) / (f.top - f.bottom) * height};
}

glm::dvec3 pixel_direction(const FaceCamera& camera, int width, int height, double x, double y) {
  const Frustum& f = camera.frustum;
  const double ex = f.left + (f.right - f.left) * x / width;
  const double ey = f.top - (f.top - f.bottom) * y / height;
  return glm::dvec3(camera.camera_to_world * glm::dvec4(ex, ey, -f.near_plane, 0.0));
}

glm::dvec3 pixel_point(const FaceCamera& camera, int width, int height, double x, double y, double z) {
  const Frustum& f = camera.frustum;
  const double scale = z / f.near_plane;
  const double ex = (f.left + (f.right - f.left) * x / width) * scale;
  const double ey = (f.top - (f.top - f.bottom) * y / height) * scale;
  return glm::dvec3(camera.camera_to_world * glm::dvec4(ex, ey, -z, 1.0));
}

int face_for_direction(const CellImages& cell, const glm::dvec3& d) {
  const glm::dvec3 unit = glm::normalize(d);
  int best = 0;
  double best_cos = -2;
  for (int f = 0; f < kFaceCount; ++f) {
    // The camera looks along its -z: the cosine between that axis and d.
    const double c = -(cell.cameras[f].world_to_camera * glm::dvec4(unit, 0.0)).z;
    if (c > best_cos) best_cos = c, best = f;
  }
  return best;
}

FaceSample locate_sample(const CellImages& cell, int face, glm::dvec2 p) {
  const int w = cell.width, h = cell.height;
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) p = {w / 2.0, h / 2.0};
  const double x = std::clamp(p.x - 0.5, 0.0, w - 1.0), y = std::clamp(p.y - 0.5, 0.0, h - 1.0);
  const int x0 = std::min(static_cast<int>(x), w - 1), y0 = std::min(static_cast<int>(y), h - 1);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  auto offset = [&](int xi, int yi) { return static_cast<uint32_t>((static_cast<size_t>(yi) * w + xi) * 4); };
  return FaceSample{face, {offset(x0, y0), offset(x1, y0), offset(x0, y1), offset(x1, y1)}, x - x0, y - y0};
}

std::array<uint8_t, 4> take_sample(const CellImages& cell, const FaceSample& s) {
  const uint8_t* rgba = cell.rgba[s.face].data();
  std::array<uint8_t, 4> out{};
  for (int c = 0; c < 4; ++c) {
    if (s.fx == 0 && s.fy == 0) {  // a texel centre: a copy, as for the cameras of a cube
      out[c] = rgba[s.offsets[0] + c];
      continue;
    }
    const double top = rgba[s.offsets[0] + c] * (1 - s.fx) + rgba[s.offsets[1] + c] * s.fx;
    const double bottom = rgba[s.offsets[2] + c] * (1 - s.fx) + rgba[s.offsets[3] + c] * s.fx;
    out[c] = static_cast<uint8_t>(std::lround(top * (1 - s.fy) + bottom * s.fy));
  }
  return out;
}

std::array<uint8_t, 4> sample_face(const CellImages& cell, int face, glm::dvec2 p) {
  return take_sample(cell, locate_sample(cell, face, p));
}

glm::dvec3 cube_texel_direction(int target, double s, double t) {
  const double sc = 2 * s - 1, tc = 2 * t - 1;
  switch (target) {
    case 0: return {1, -tc, -sc};    // +X: sc = -rz, tc = -ry
    case 1: return {-1, -tc, sc};    // -X: sc = +rz, tc = -ry
    case 2: return {sc, 1, tc};      // +Y: sc = +rx, tc = +rz
    case 3: return {sc, -1, -tc};    // -Y: sc = +rx, tc = -rz
    case 4: return {sc, -tc, 1};     // +Z: sc = +rx, tc = -ry
    default: return {-sc, -tc, -1};  // -Z: sc = -rx, tc = -ry
  }
}

CubeMapLayout::CubeMapLayout(const CellImages& cell, int size) : size_(size) {
  for (int f = 0; f < kFaceCount; ++f) cameras_[f] = cell.cameras[f];
  face_width_ = cell.width;
  face_height_ = cell.height;
  for (int target = 0; target < kCubeTargets; ++target) {
    std::vector<FaceSample>& samples = samples_[target];
    samples.reserve(static_cast<size_t>(size) * size);
    for (int row = 0; row < size; ++row) {
      for (int column = 0; column < size; ++column) {
        const glm::dvec3 d = cube_texel_direction(target, (column + 0.5) / size, (row + 0.5) / size);
        const int face = face_for_direction(cell, d);
        samples.push_back(
            locate_sample(cell, face, project_direction(cell.cameras[face], cell.width, cell.height, d)));
      }
    }
  }
}

bool CubeMapLayout::fits(const CellImages& cell) const {
  if (cell.width != face_width_ || cell.height != face_height_) return false;
  for (int f = 0; f < kFaceCount; ++f) {
    const FaceCamera& a = cameras_[f];
    const FaceCamera& b = cell.cameras[f];
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) {
        if (a.world_to_camera[c][r] != b.world_to_camera[c][r]) return false;
      }
    }
    const Frustum &p = a.frustum, &q = b.frustum;
    if (p.left != q.left || p.right != q.right || p.bottom != q.bottom || p.top != q.top ||
        p.near_plane != q.near_plane) {
      return false;
    }
  }
  return true;
}

std::vector<uint8_t> CubeMapLayout::face(const CellImages& cell, int target) const {
  std::vector<uint8_t> texels(static_cast<size_t>(size_) * size_ * 4);
  uint8_t* out = texels.data();
  for (const FaceSample& s : samples_[target]) {
    const auto rgba = take_sample(cell, s);
    out = std::copy(rgba.begin(), rgba.end(), out);
  }
  return texels;
}

std::vector<uint8_t> cube_map_face(const CellImages& cell, int target, int size) {
  return CubeMapLayout(cell, size).face(cell, target);
}

}  // namespace svc::viewer
