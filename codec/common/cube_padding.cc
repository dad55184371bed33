// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/cube_padding.h"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "codec/common/cube_padding_map.h"
#include "codec/common/integer_division.h"

namespace svc::codec {

namespace {

using Axis = std::array<int, 3>;

// Per face, the world directions of its image axes: right (+column), down (+row) and
// forward, from the face cameras of docs/input-format.md (right = forward x up).
struct FaceFrame {
  Axis right, down, forward;
};

constexpr std::array<FaceFrame, kFaceCount> kFrames = {{
    {{0, 0, 1}, {0, -1, 0}, {1, 0, 0}},    // px
    {{0, 0, -1}, {0, -1, 0}, {-1, 0, 0}},  // nx
    {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},    // py
    {{-1, 0, 0}, {0, 0, -1}, {0, -1, 0}},  // ny
    {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}},   // pz
    {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}},   // nz
}};

long long dot(const Axis& axis, long long x, long long y, long long z) {
  return axis[0] * x + axis[1] * y + axis[2] * z;
}

constexpr int face_looking_along(const Axis& axis, int sign) {
  for (int g = 0; g < kFaceCount; ++g) {
    const Axis& f = kFrames[g].forward;
    if (f[0] == sign * axis[0] && f[1] == sign * axis[1] && f[2] == sign * axis[2]) return g;
  }
  return 0;  // unreachable: every signed axis is some face's forward direction
}

// The face across each edge: [face][0 across columns, 1 across rows][0 towards minus, 1
// towards plus], tabulated for the border map's every sample.
constexpr std::array<std::array<std::array<int, 2>, 2>, kFaceCount> kFaceAcross = [] {
  std::array<std::array<std::array<int, 2>, 2>, kFaceCount> table{};
  for (int face = 0; face < kFaceCount; ++face) {
    for (int sign = 0; sign < 2; ++sign) {
      table[face][0][sign] = face_looking_along(kFrames[face].right, 2 * sign - 1);
      table[face][1][sign] = face_looking_along(kFrames[face].down, 2 * sign - 1);
    }
  }
  return table;
}();

// 1/16-sample position along one axis of an n-sample face for face coordinate p / c
// (-1 .. 1 across the face; c > 0, the depth of a border sample along the face it
// shows): 16 ((p / c + 1) n / 2 - 1/2), rounded half up.
int sixteenth_position(long long p, long long c, int n) {
  return static_cast<int>(floor_divide(16 * (p * n + (n - 1) * c) + c, 2 * c));
}

// Bilinear sample at 1/16 position (x16, y16) of an n x n plane, edge-clamped.
int bilinear_sample(const uint8_t* plane, int n, int x16, int y16) {
  const int ix = x16 >> 4, fx = x16 & 15, iy = y16 >> 4, fy = y16 & 15;
  auto s = [&](int u, int v) -> int {
    return plane[static_cast<size_t>(std::clamp(v, 0, n - 1)) * n + std::clamp(u, 0, n - 1)];
  };
  return ((16 - fx) * (16 - fy) * s(ix, iy) + fx * (16 - fy) * s(ix + 1, iy) + (16 - fx) * fy * s(ix, iy + 1) +
          fx * fy * s(ix + 1, iy + 1) + 128) >>
         8;
}

}  // namespace

namespace cube_padding_internal {

BorderSource border_source(int face, int n, int i, int j) {
  const FaceFrame& frame = kFrames[face];
  // Pixel centre in units of half a sample from the face centre; the face spans +-n.
  const long long a = 2LL * i + 1 - n, b = 2LL * j + 1 - n, c = n;
  const long long x = a * frame.right[0] + b * frame.down[0] + c * frame.forward[0];
  const long long y = a * frame.right[1] + b * frame.down[1] + c * frame.forward[1];
  const long long z = a * frame.right[2] + b * frame.down[2] + c * frame.forward[2];
  // The direction leaves through the face whose axis dominates; on a diagonal, the
  // neighbour across the left or right edge.
  const int g = std::llabs(a) >= std::llabs(b) ? kFaceAcross[face][0][a > 0] : kFaceAcross[face][1][b > 0];
  const FaceFrame& target = kFrames[g];
  const long long depth = dot(target.forward, x, y, z);
  return {g, sixteenth_position(dot(target.right, x, y, z), depth, n),
          sixteenth_position(dot(target.down, x, y, z), depth, n)};
}

void pad_plane_reference(const FacePlanes& planes, int face, int n, int border, std::vector<uint8_t>* out) {
  const int size = n + 2 * border;
  out->assign(static_cast<size_t>(size) * size, 0);
  for (int j = -border; j < n + border; ++j) {
    uint8_t* row = out->data() + static_cast<size_t>(j + border) * size + border;
    const bool row_inside = j >= 0 && j < n;
    for (int i = -border; i < n + border; ++i) {
      if (row_inside && i >= 0 && i < n) {
        row[i] = (*planes[face])[static_cast<size_t>(j) * n + i];
        continue;
      }
      const BorderSource source = border_source(face, n, i, j);
      const std::vector<uint8_t>* plane = planes[source.face];
      row[i] = plane == nullptr ? 0
                                : static_cast<uint8_t>(bilinear_sample(plane->data(), n, source.x16, source.y16));
    }
  }
}

}  // namespace cube_padding_internal

std::array<Face, 4> adjacent_faces(Face face) {
  std::array<Face, 4> out{};
  const int opposite = static_cast<int>(face) ^ 1;
  int k = 0;
  for (int g = 0; g < kFaceCount; ++g) {
    if (g != static_cast<int>(face) && g != opposite) out[k++] = static_cast<Face>(g);
  }
  return out;
}

Face face_across(Face face, FaceEdge edge) {
  const bool plus = edge == FaceEdge::kRight || edge == FaceEdge::kBottom;
  const bool across_columns = edge == FaceEdge::kLeft || edge == FaceEdge::kRight;
  return static_cast<Face>(kFaceAcross[static_cast<int>(face)][across_columns ? 0 : 1][plus ? 1 : 0]);
}

bool border_edges_show(Face face, uint8_t edges, Face g) {
  for (int e = 0; e < kFaceEdgeCount; ++e) {
    if ((edges >> e & 1) != 0 && face_across(face, static_cast<FaceEdge>(e)) == g) return true;
  }
  return false;
}

namespace {

// Smallest |2t + 1 - size| over integers t in lo..hi: the distance from the face centre,
// in half samples, of the window's nearest column (or row).
long long nearest_to_centre(int lo, int hi, int size) {
  const int below = std::clamp((size - 1) / 2, lo, hi), above = std::clamp((size - 1) / 2 + 1, lo, hi);
  return std::min(std::llabs(2LL * below + 1 - size), std::llabs(2LL * above + 1 - size));
}

}  // namespace

uint8_t border_edges_in_window(int size, int border, int x0, int y0, int x1, int y1) {
  const int last = size + 2 * border - 1;
  // Face coordinates of the clamped window; border_source's rule: a border sample (i, j)
  // shows the left or right face when |2i + 1 - size| >= |2j + 1 - size|, else the top or
  // bottom face. The window's outermost column (row) is the farthest from the centre.
  const int i0 = std::clamp(x0, 0, last) - border, i1 = std::clamp(x1, 0, last) - border;
  const int j0 = std::clamp(y0, 0, last) - border, j1 = std::clamp(y1, 0, last) - border;
  if (i0 >= 0 && j0 >= 0 && i1 < size && j1 < size) return 0;
  const long long row_nearest = nearest_to_centre(j0, j1, size), column_nearest = nearest_to_centre(i0, i1, size);
  uint8_t edges = 0;
  if (i0 < 0 && row_nearest <= size - 1 - 2LL * i0) edges |= 1u << static_cast<int>(FaceEdge::kLeft);
  if (i1 >= size && row_nearest <= 2LL * i1 + 1 - size) edges |= 1u << static_cast<int>(FaceEdge::kRight);
  if (j0 < 0 && column_nearest < size - 1 - 2LL * j0) edges |= 1u << static_cast<int>(FaceEdge::kTop);
  if (j1 >= size && column_nearest < 2LL * j1 + 1 - size) edges |= 1u << static_cast<int>(FaceEdge::kBottom);
  return edges;
}

Status pad_cube_face(const CubeFaces& cube, Face face, int units, ImageYCbCr420* out) {
  if (units < 0 || units > kMaxCubeBorderUnits) {
    return Status(ErrorCode::kInvalidArgument, "cube border of " + std::to_string(units) + " units outside 0.." +
                                                   std::to_string(kMaxCubeBorderUnits));
  }
  const int f = static_cast<int>(face);
  if (f < 0 || f >= kFaceCount || cube[f] == nullptr) {
    return Status(ErrorCode::kInvalidArgument,
                  f < 0 || f >= kFaceCount ? "cube padding: face " + std::to_string(f) + " outside px..nz"
                                           : "cube padding: face " + std::string(face_name(face)) + " missing");
  }
  const int n = cube[f]->width;
  if (!cube_padding_possible(cube[f]->width, cube[f]->height)) {
    return Status(ErrorCode::kInvalidArgument, "cube padding: face " + std::string(face_name(face)) + " is " +
                                                   std::to_string(cube[f]->width) + "x" +
                                                   std::to_string(cube[f]->height) + ", not square");
  }
  const int nc = (n + 1) / 2;
  const size_t luma = static_cast<size_t>(n) * n, chroma = static_cast<size_t>(nc) * nc;
  std::array<Face, 5> needed{face};
  const std::array<Face, 4> adjacent = adjacent_faces(face);
  std::copy(adjacent.begin(), adjacent.end(), needed.begin() + 1);
  for (Face g : needed) {
    const ImageYCbCr420* image = cube[static_cast<int>(g)];
    if (image == nullptr) continue;  // face `face` itself was checked above
    if (image->width != n || image->height != n || image->y.size() != luma || image->cb.size() != chroma ||
        image->cr.size() != chroma) {
      return Status(ErrorCode::kInvalidArgument, "cube padding of face " + std::string(face_name(face)) +
                                                     ": face " + face_name(g) + " is missing or not " +
                                                     std::to_string(n) + "x" + std::to_string(n) + " 4:2:0");
    }
  }
  const int border = units * kCubeBorderUnitPixels;
  cube_padding_internal::FacePlanes y{}, cb{}, cr{};
  for (Face g : needed) {
    const int k = static_cast<int>(g);
    if (cube[k] == nullptr) continue;
    y[k] = &cube[k]->y;
    cb[k] = &cube[k]->cb;
    cr[k] = &cube[k]->cr;
  }
  ImageYCbCr420 padded;
  padded.width = padded.height = n + 2 * border;
  cube_padding_internal::pad_plane(y, f, n, border, &padded.y);
  cube_padding_internal::pad_plane(cb, f, nc, border / 2, &padded.cb);
  cube_padding_internal::pad_plane(cr, f, nc, border / 2, &padded.cr);
  *out = std::move(padded);
  return Status::Ok();
}

}  // namespace svc::codec
