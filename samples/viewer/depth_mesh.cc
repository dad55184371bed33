// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/depth_mesh.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace svc::viewer {

namespace {

// Where a face's vertices stand along one axis of `pixels` pixels, in continuous pixel
// coordinates: the face's edge, the centre of every step-th pixel, the other edge.
std::vector<double> vertex_coordinates(int pixels, int step) {
  std::vector<double> out = {0.0};
  for (int p = 0; p < pixels; p += step) out.push_back(p + 0.5);
  out.push_back(pixels);
  return out;
}
// The pixel whose depth a vertex takes.
int vertex_pixel(double coordinate, int pixels) { return std::clamp(static_cast<int>(coordinate), 0, pixels - 1); }

// Appends the face's vertices; returns, per vertex, whether it stands on geometry.
std::vector<bool> add_face_vertices(const CellImages& cell, int face, const std::vector<double>& xs,
                                    const std::vector<double>& ys, DepthMesh* mesh) {
  const int w = cell.width, h = cell.height;
  const std::vector<float>& depth = cell.depth[face];
  std::vector<bool> solid;
  solid.reserve(xs.size() * ys.size());
  for (double y : ys) {
    for (double x : xs) {
      const float z = depth[static_cast<size_t>(vertex_pixel(y, h)) * w + vertex_pixel(x, w)];
      const bool finite = std::isfinite(z) && z > 0;
      const glm::dvec3 p = finite ? pixel_point(cell.cameras[face], w, h, x, y, z) - cell.centre : glm::dvec3(0.0);
      mesh->positions.insert(mesh->positions.end(),
                             {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
      solid.push_back(finite);
    }
  }
  return solid;
}

glm::dvec3 vertex(const DepthMesh& mesh, uint32_t index) {
  return {mesh.positions[index * 3], mesh.positions[index * 3 + 1], mesh.positions[index * 3 + 2]};
}

// Whether the triangle is seen from the centre (the origin) at more than
// `min_grazing_sine` (the sine of its grazing angle).
bool faces_centre(const DepthMesh& mesh, uint32_t a, uint32_t b, uint32_t c, double min_grazing_sine) {
  const glm::dvec3 pa = vertex(mesh, a), pb = vertex(mesh, b), pc = vertex(mesh, c);
  const glm::dvec3 normal = glm::cross(pb - pa, pc - pa);
  const glm::dvec3 centroid = (pa + pb + pc) / 3.0;
  const double n = glm::length(normal), r = glm::length(centroid);
  if (n == 0 || r == 0) return false;
  return std::abs(glm::dot(normal, centroid)) > min_grazing_sine * n * r;
}

void add_triangle(DepthMesh* mesh, const std::vector<bool>& solid, uint32_t base, uint32_t a, uint32_t b,
                  uint32_t c, double min_grazing_sine) {
  if (!solid[a] || !solid[b] || !solid[c] || !faces_centre(*mesh, base + a, base + b, base + c, min_grazing_sine)) {
    ++mesh->triangles_dropped;
    return;
  }
  mesh->indices.insert(mesh->indices.end(), {base + a, base + b, base + c});
}

}  // namespace

int mesh_step(int face_size) { return std::max(1, (face_size + kMeshVerticesAcross - 1) / kMeshVerticesAcross); }

DepthMesh build_depth_mesh(const CellImages& cell) {
  DepthMesh mesh;
  const int w = cell.width, h = cell.height, step = mesh_step(std::max(w, h));
  const std::vector<double> xs = vertex_coordinates(w, step), ys = vertex_coordinates(h, step);
  // A 90-degree face of w pixels spans about 2 / w radians a pixel.
  const double min_grazing_sine = std::sin(kMinGrazingPixels * step * 2.0 / std::max(w, h));
  for (int face = 0; face < kFaceCount; ++face) {
    if (cell.depth[face].size() != static_cast<size_t>(w) * h) continue;
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size() / 3);
    const std::vector<bool> solid = add_face_vertices(cell, face, xs, ys, &mesh);
    const uint32_t row = static_cast<uint32_t>(xs.size());
    for (uint32_t j = 0; j + 1 < ys.size(); ++j) {
      for (uint32_t i = 0; i + 1 < row; ++i) {
        const uint32_t v00 = j * row + i, v10 = v00 + 1, v01 = v00 + row, v11 = v01 + 1;
        add_triangle(&mesh, solid, base, v00, v01, v10, min_grazing_sine);
        add_triangle(&mesh, solid, base, v10, v01, v11, min_grazing_sine);
      }
    }
  }
  return mesh;
}

}  // namespace svc::viewer
