// SPDX-License-Identifier: BSD-2-Clause
// A cell's faces as a mesh in the world, from their depth: what lets the viewer show a
// cell from any point near it rather than from its centre alone.
//
// Each face becomes a grid of vertices, one on the ray of every pixel (every step-th
// pixel of large faces) at the pixel's depth, plus a ring on the face's edges (at the
// depth of the edge pixel) so that neighbouring faces meet along the cube's edges. The
// colour does not come from the vertices but from the cube map, per fragment, so a
// coarser grid blurs only the geometry. Triangles that would stretch across a depth
// discontinuity, or touch a pixel that saw nothing (sky), are left out: the viewer shows
// the cube map at infinity through those holes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "viewer/cell_images.h"

namespace svc::viewer {

struct DepthMesh {
  std::vector<float> positions;   // x, y, z per vertex, relative to the cell's centre
  std::vector<uint32_t> indices;  // three per triangle
  size_t triangles_dropped = 0;
};

// A triangle is kept when it faces the cell's centre at more than this many pixel
// widths of grazing angle. The strip joining a foreground edge to the background behind
// it is seen edge-on from the centre (its grazing angle is about a pixel's angle times
// near depth / depth gap), while real surfaces are seen that steeply only far away.
inline constexpr double kMinGrazingPixels = 2.0;

// Vertices across a face at most (plus the edges): 128 keeps a cell's mesh near 200,000
// triangles, which a software renderer still draws at interactive rates, while 64-pixel
// faces get a vertex on every pixel.
inline constexpr int kMeshVerticesAcross = 128;
// Pixels between vertices for faces of `face_size` pixels.
int mesh_step(int face_size);

// The mesh of every face of `cell` with depth; empty when it has none.
DepthMesh build_depth_mesh(const CellImages& cell);

}  // namespace svc::viewer
