// SPDX-License-Identifier: BSD-2-Clause
// What one cube map sees of another: the estimate behind reference choice and I-cube
// placement by visibility (spatial/placement.h). A B-cube is sampled at every
// kVisibilitySampleStep-th pixel of each face in each direction; a sample point counts as
// seen by a reference cube when it lands inside any of the reference's six faces, in
// front of that face's camera, and is not hidden there (see seen_by).
//
// Conventions as in spatial/reprojection.h (eye z depth, OpenGL cameras, pixel centres).
// Threading: pure functions of their arguments; safe to call concurrently.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "svc/types.h"

namespace svc {

// Pixels between samples along each axis of a face: 1/16 of the pixels of a face.
inline constexpr int kVisibilitySampleStep = 4;

// A cube map's geometry at reduced resolution: per face its camera and the eye depth of
// pixel (step * i + step / 2, step * j + step / 2), row-major, for i < width, j < height.
struct CubeSamples {
  int step = kVisibilitySampleStep;
  int face_width = 0, face_height = 0;  // full-resolution face size
  int width = 0, height = 0;            // samples per row and per column of a face
  std::array<Camera, kFaceCount> cameras;
  std::array<std::vector<float>, kFaceCount> depth;
};

// Samples of one face of a face_width x face_height cube with `camera` and full-resolution
// eye depth `depth` (row-major, face_width * face_height values) into `cube`. Every face
// of a cube must be added with the same size and step (the first call sets them). Returns
// false, leaving `cube` unchanged, when the depth size does not match or the size or step
// differs from the cube's.
bool add_face_samples(CubeSamples* cube, Face face, const Camera& camera, int face_width, int face_height,
                      const std::vector<float>& depth, int step = kVisibilitySampleStep);

// Sample points of a cube: kFaceCount * width * height, face-major then row-major.
size_t sample_count(const CubeSamples& cube);

// Relative depth margin by which a sample point may lie behind the surface a reference
// face shows there and still count as seen (as kVisibilityTolerance of reprojection.h).
inline constexpr double kSampledVisibilityTolerance = 0.02;

// Which sample points of `current` the cube `reference` sees, as a bitset of
// sample_count(current) bits (bit k of word k / 64). A point is seen when it lands
// inside a face of `reference` in front of its near plane and is not hidden there: its
// eye depth in that face is at most (1 + kSampledVisibilityTolerance) times the largest
// depth of the 2x2 samples around where it lands (clamped to the face; background
// samples count as infinitely far). Between samples of one surface the point's depth
// lies within theirs, so only a nearer surface hides it. A background point of `current` (a direction) is seen when
// one of those samples is background too. Empty when either cube has no samples.
std::vector<uint64_t> seen_by(const CubeSamples& current, const CubeSamples& reference);

// Bits set in the union of `a` and `b` (same length).
size_t count_seen_by_either(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b);

}  // namespace svc
