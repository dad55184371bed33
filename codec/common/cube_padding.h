// SPDX-License-Identifier: BSD-2-Clause
// Geometry padding of cube-map reference faces: a face extended by a border in which
// each sample shows what the same camera would see past the face edge, taken from the
// adjacent faces of the same cube (the cube-map projection continued across the edge,
// as 360-degree video coders pad cube maps). Motion vectors of a B-face that leave the
// reference face then find the right content instead of repeated edge samples.
// Integer arithmetic only: part of the bitstream contract (docs/codec.md, section 5.7).
//
// All functions are thread-safe. The border geometry of each face size is worked out
// once and kept for later paddings (codec/cube_padding_map.h).
#pragma once

#include <array>
#include <cstdint>

#include "svc/status.h"
#include "svc/types.h"

namespace svc::codec {

// A border is a whole number of macroblocks wide (16 luma, 8 chroma samples a unit), so
// macroblock (mx, my) of a face is macroblock (mx + units, my + units) of its padded
// reference. The B-face header stores the unit count (0 = no padding).
inline constexpr int kCubeBorderUnitPixels = 16;
inline constexpr int kMaxCubeBorderUnits = 4;

// The four faces sharing an edge with `face` (every face but itself and its opposite),
// in face order px, nx, py, ny, pz, nz.
std::array<Face, 4> adjacent_faces(Face face);

// The four edges of a face, each the side whose border shows one adjacent face
// (face_across): left (before column 0), right, top (before row 0), bottom.
enum class FaceEdge : uint8_t { kLeft = 0, kRight = 1, kTop = 2, kBottom = 3 };
inline constexpr int kFaceEdgeCount = 4;
inline constexpr uint8_t kAllFaceEdges = 0xF;

// The adjacent face whose samples fill the border across `edge` of `face`.
Face face_across(Face face, FaceEdge edge);

// Whether `edges` (FaceEdge bits of `face`) include the edge across which adjacent face
// `g` lies: the faces a border limited to those edges is padded from.
bool border_edges_show(Face face, uint8_t edges, Face g);

// Bit e set for each FaceEdge e some of whose border samples (those taken from
// face_across(face, e), docs/codec.md 5.7) lie in columns x0..x1 and rows y0..y1 of a
// plane of `size` samples a side padded by `border` (padded-plane coordinates), the
// window first clamped to the plane as motion compensation clamps reads.
uint8_t border_edges_in_window(int size, int border, int x0, int y0, int x1, int y1);

// Whether faces of this size can be padded: cube faces are square.
inline bool cube_padding_possible(int width, int height) { return width == height && width > 0; }

// The six faces of one cube map, indexed by Face. Only the padded face and its adjacent
// faces are read; the opposite face may be null, and so may adjacent faces whose border
// samples no prediction reads (their samples are then 0, see BorderEdges in
// codec/decoder/bframe_decoder.h).
using CubeFaces = std::array<const ImageYCbCr420*, kFaceCount>;

// The reference face `face` of `cube` with a border of `units` x 16 luma samples on each
// side: (n + 32 units)^2 luma samples for n x n faces, chroma planes likewise with half
// the border. Inside, the face's own samples; in the border, the adjacent face hit by
// the same viewing direction, sampled bilinearly at 1/16 sample (docs/codec.md 5.7).
// Errors (kInvalidArgument): units outside 0..kMaxCubeBorderUnits, faces that are not
// square, of different sizes, or face `face` missing. `out` is unchanged then.
Status pad_cube_face(const CubeFaces& cube, Face face, int units, ImageYCbCr420* out);

}  // namespace svc::codec
