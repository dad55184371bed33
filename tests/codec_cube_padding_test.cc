// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <random>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/cube_padding.h"
#include "codec/common/cube_padding_map.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "support/reference_hints.h"

namespace svc::codec {
namespace {

using Vec = std::array<double, 3>;

// The face cameras of docs/input-format.md (as the sample generator writes them), kept
// here independently of the codec's integer tables.
constexpr Vec kForward[kFaceCount] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
constexpr Vec kUp[kFaceCount] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// World direction through pixel (i, j) of an n x n face (i, j may lie outside the face),
// optionally with the camera turned by `yaw` radians about +y.
Vec pixel_direction(int face, double i, double j, int n, double yaw = 0) {
  const Vec right = cross(kForward[face], kUp[face]);
  const double x = (i + 0.5) / n * 2 - 1, y = 1 - (j + 0.5) / n * 2;
  Vec d;
  for (int k = 0; k < 3; ++k) d[k] = right[k] * x + kUp[face][k] * y + kForward[face][k];
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]};
}

// The face a direction hits, or -1 when two axes tie (a cube edge or corner).
int face_hit(const Vec& d) {
  int best = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(d[k]) > std::abs(d[best])) best = k;
  }
  for (int k = 0; k < 3; ++k) {
    if (k != best && std::abs(std::abs(d[k]) - std::abs(d[best])) < 1e-9) return -1;
  }
  return 2 * best + (d[best] < 0 ? 1 : 0);
}

ImageYCbCr420 blank_face(int n) {
  ImageYCbCr420 image;
  image.width = image.height = n;
  image.y.assign(static_cast<size_t>(n) * n, 0);
  image.cb.assign(static_cast<size_t>((n + 1) / 2) * ((n + 1) / 2), 0);
  image.cr.assign(image.cb.size(), 0);
  return image;
}

// A smooth environment: a value for every direction, the same whichever face sees it.
double environment(const Vec& d, int plane) {
  const double len = std::sqrt(dot(d, d));
  const Vec u = {d[0] / len, d[1] / len, d[2] / len};
  const Vec k = plane == 0 ? Vec{0.31, 0.52, 0.79} : Vec{-0.6, 0.2, 0.77};
  return 128 + 90 * dot(u, k) + 20 * std::sin(3 * u[0] + 2 * u[1] - u[2] + plane);
}

// Busier content for coding tests: detail at a few pixels' scale on 64-pixel faces.
double textured_environment(const Vec& d, int plane) {
  const double len = std::sqrt(dot(d, d));
  const Vec u = {d[0] / len, d[1] / len, d[2] / len};
  return 128 + 50 * std::sin(9 * u[0] + 5 * u[1] + plane) * std::cos(7 * u[2] - 4 * u[1]) +
         30 * std::sin(13 * u[2] + 11 * u[0] + 2 * plane);
}

template <typename Value>
ImageYCbCr420 render_face(int face, int n, Value value, double yaw = 0) {
  ImageYCbCr420 image = blank_face(n);
  const int nc = (n + 1) / 2;
  auto byte = [](double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0))); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i)
      image.y[static_cast<size_t>(j) * n + i] = byte(value(pixel_direction(face, i, j, n, yaw), 0));
  }
  for (int j = 0; j < nc; ++j) {
    for (int i = 0; i < nc; ++i) {
      image.cb[static_cast<size_t>(j) * nc + i] = byte(value(pixel_direction(face, i, j, nc, yaw), 1));
      image.cr[static_cast<size_t>(j) * nc + i] = byte(value(pixel_direction(face, i, j, nc, yaw), 2));
    }
  }
  return image;
}

CubeFaces pointers(const std::array<ImageYCbCr420, kFaceCount>& faces) {
  CubeFaces cube{};
  for (int f = 0; f < kFaceCount; ++f) cube[f] = &faces[f];
  return cube;
}

TEST(CubePadding, AdjacentFacesAreTheFourSharingAnEdge) {
  for (int f = 0; f < kFaceCount; ++f) {
    const std::array<Face, 4> adjacent = adjacent_faces(static_cast<Face>(f));
    for (Face g : adjacent) {
      // Adjacent faces look along perpendicular axes.
      EXPECT_EQ(dot(kForward[f], kForward[static_cast<int>(g)]), 0.0) << f << " " << static_cast<int>(g);
    }
    EXPECT_EQ(std::set<Face>(adjacent.begin(), adjacent.end()).size(), 4u);
  }
}

// Constant faces: every border sample must come from the face its direction hits, for
// all 24 face edges and the corners beyond two edges.
TEST(CubePadding, BorderSamplesComeFromTheFaceTheDirectionHits) {
  const int n = 48, units = 2, border = 32;
  std::array<ImageYCbCr420, kFaceCount> faces;
  for (int f = 0; f < kFaceCount; ++f) {
    faces[f] = blank_face(n);
    std::fill(faces[f].y.begin(), faces[f].y.end(), static_cast<uint8_t>(20 + 40 * f));
    std::fill(faces[f].cb.begin(), faces[f].cb.end(), static_cast<uint8_t>(200 - 30 * f));
    std::fill(faces[f].cr.begin(), faces[f].cr.end(), static_cast<uint8_t>(7 + 11 * f));
  }
  std::set<std::pair<int, int>> edges;
  for (int f = 0; f < kFaceCount; ++f) {
    ImageYCbCr420 padded;
    ASSERT_TRUE(pad_cube_face(pointers(faces), static_cast<Face>(f), units, &padded).ok());
    ASSERT_EQ(padded.width, n + 2 * border);
    ASSERT_EQ(padded.height, n + 2 * border);
    const int size = padded.width;
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const int g = face_hit(pixel_direction(f, i - border, j - border, n));
        if (g < 0) continue;
        if (g != f) edges.insert({f, g});
        ASSERT_EQ(padded.y[static_cast<size_t>(j) * size + i], faces[g].y[0]) << f << " (" << i << ", " << j << ")";
      }
    }
    const int nc = n / 2, bc = border / 2, sc = nc + 2 * bc;
    ASSERT_EQ(padded.cb.size(), static_cast<size_t>(sc) * sc);
    for (int j = 0; j < sc; ++j) {
      for (int i = 0; i < sc; ++i) {
        const int g = face_hit(pixel_direction(f, i - bc, j - bc, nc));
        if (g < 0) continue;
        ASSERT_EQ(padded.cb[static_cast<size_t>(j) * sc + i], faces[g].cb[0]) << f << " (" << i << ", " << j << ")";
        ASSERT_EQ(padded.cr[static_cast<size_t>(j) * sc + i], faces[g].cr[0]) << f << " (" << i << ", " << j << ")";
      }
    }
  }
  EXPECT_EQ(edges.size(), 24u);  // each face's border reaches its four neighbours
}

// A smooth environment: the padded face shows, at every border sample, the value its
// viewing direction has, so the content continues across each edge in the right
// orientation (a mirrored or rotated neighbour would be off by tens of levels).
TEST(CubePadding, BorderContinuesTheEnvironmentAcrossEveryEdge) {
  const int n = 64, units = 2, border = 32;
  std::array<ImageYCbCr420, kFaceCount> faces;
  for (int f = 0; f < kFaceCount; ++f) faces[f] = render_face(f, n, environment);
  for (int f = 0; f < kFaceCount; ++f) {
    ImageYCbCr420 padded;
    ASSERT_TRUE(pad_cube_face(pointers(faces), static_cast<Face>(f), units, &padded).ok());
    const int size = padded.width;
    double worst = 0;
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const double expected = environment(pixel_direction(f, i - border, j - border, n), 0);
        const bool inside = i >= border && j >= border && i < border + n && j < border + n;
        const double got = padded.y[static_cast<size_t>(j) * size + i];
        if (inside) {
          ASSERT_EQ(got, faces[f].y[static_cast<size_t>(j - border) * n + (i - border)]);
        } else {
          worst = std::max(worst, std::abs(got - expected));
        }
      }
    }
    EXPECT_LE(worst, 2.5) << "face " << f;
    const int nc = n / 2, bc = border / 2, sc = nc + 2 * bc;
    double worst_chroma = 0;
    for (int j = 0; j < sc; ++j) {
      for (int i = 0; i < sc; ++i) {
        const double expected = environment(pixel_direction(f, i - bc, j - bc, nc), 1);
        worst_chroma = std::max(worst_chroma, std::abs(padded.cb[static_cast<size_t>(j) * sc + i] - expected));
      }
    }
    EXPECT_LE(worst_chroma, 3.0) << "face " << f;
  }
}

TEST(CubePadding, OppositeFaceIsNotNeededAndZeroUnitsCopiesTheFace) {
  std::array<ImageYCbCr420, kFaceCount> faces;
  for (int f = 0; f < kFaceCount; ++f) faces[f] = render_face(f, 32, environment);
  CubeFaces cube = pointers(faces);
  cube[static_cast<int>(Face::kNZ)] = nullptr;
  ImageYCbCr420 padded;
  ASSERT_TRUE(pad_cube_face(cube, Face::kPZ, 1, &padded).ok());
  EXPECT_EQ(padded.width, 64);
  ASSERT_TRUE(pad_cube_face(cube, Face::kPZ, 0, &padded).ok());
  EXPECT_EQ(padded.y, faces[4].y);
  EXPECT_EQ(padded.cb, faces[4].cb);
  EXPECT_EQ(padded.cr, faces[4].cr);
}

// Uniformly random samples (extremes included) on all six faces.
std::array<ImageYCbCr420, kFaceCount> random_faces(int n, std::mt19937& rng) {
  std::uniform_int_distribution<int> sample(0, 255);
  std::array<ImageYCbCr420, kFaceCount> faces;
  for (ImageYCbCr420& face : faces) {
    face = blank_face(n);
    for (std::vector<uint8_t>* plane : {&face.y, &face.cb, &face.cr}) {
      for (uint8_t& v : *plane) v = static_cast<uint8_t>(sample(rng));
    }
  }
  return faces;
}

// Face `f` padded by the per-sample rule of docs/codec.md 5.7, plane by plane.
ImageYCbCr420 reference_padding(const std::array<ImageYCbCr420, kFaceCount>& faces, int f, int units) {
  cube_padding_internal::FacePlanes y{}, cb{}, cr{};
  for (int g = 0; g < kFaceCount; ++g) {
    if (g == (f ^ 1)) continue;  // the opposite face is never read
    y[g] = &faces[g].y;
    cb[g] = &faces[g].cb;
    cr[g] = &faces[g].cr;
  }
  const int n = faces[f].width, nc = (n + 1) / 2, border = units * kCubeBorderUnitPixels;
  ImageYCbCr420 padded;
  padded.width = padded.height = n + 2 * border;
  cube_padding_internal::pad_plane_reference(y, f, n, border, &padded.y);
  cube_padding_internal::pad_plane_reference(cb, f, nc, border / 2, &padded.cb);
  cube_padding_internal::pad_plane_reference(cr, f, nc, border / 2, &padded.cr);
  return padded;
}

// Index of the first differing sample, -1 when equal (a short message on failure).
long first_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size()) return static_cast<long>(std::min(a.size(), b.size()));
  const auto differ = std::mismatch(a.begin(), a.end(), b.begin());
  return differ.first == a.end() ? -1 : static_cast<long>(differ.first - a.begin());
}

// The precomputed border maps give exactly the samples of the per-sample rule: every
// face and border, corners included, odd sizes and planes down to 2 x 2, where most taps
// are clamped (1 x 1 planes, too small for the maps, are padded by the rule itself).
TEST(CubePadding, MappedPaddingMatchesThePerSampleRule) {
  std::mt19937 rng(1406);
  for (int n : {1, 2, 3, 7, 8, 16, 33, 64}) {
    const std::array<ImageYCbCr420, kFaceCount> faces = random_faces(n, rng);
    for (int units = 0; units <= kMaxCubeBorderUnits; ++units) {
      for (int f = 0; f < kFaceCount; ++f) {
        CubeFaces cube = pointers(faces);
        cube[f ^ 1] = nullptr;
        ImageYCbCr420 padded;
        ASSERT_TRUE(pad_cube_face(cube, static_cast<Face>(f), units, &padded).ok());
        const ImageYCbCr420 expected = reference_padding(faces, f, units);
        EXPECT_EQ(padded.width, expected.width);
        EXPECT_EQ(padded.height, expected.height);
        EXPECT_EQ(first_difference(padded.y, expected.y), -1) << "n " << n << " units " << units << " face " << f;
        EXPECT_EQ(first_difference(padded.cb, expected.cb), -1) << "n " << n << " units " << units << " face " << f;
        EXPECT_EQ(first_difference(padded.cr, expected.cr), -1) << "n " << n << " units " << units << " face " << f;
      }
    }
  }
}

// Every tap reads a whole 2 x 2 block inside its plane, clamped edges included, with
// weights whose products sum to the bilinear filter's 256 (16 per axis).
TEST(CubePadding, BorderTapsStayInsideTheirPlane) {
  for (int n : {2, 3, 7, 8, 33}) {
    for (int border : {8, 16, 64}) {
      for (int f = 0; f < kFaceCount; ++f) {
        const cube_padding_internal::BorderMap map = cube_padding_internal::build_border_map(f, n, border);
        ASSERT_EQ(map.indices.size(), static_cast<size_t>((n + 2 * border) * (n + 2 * border) - n * n));
        ASSERT_EQ(map.weights.size(), map.indices.size());
        for (uint32_t index : map.indices) {
          ASSERT_LE(static_cast<int>(index % n), n - 2) << n << " " << border << " " << f;
          ASSERT_LE(static_cast<int>(index / n), n - 2) << n << " " << border << " " << f;
        }
        for (const dsp::BilinearWeights& w : map.weights) {
          ASSERT_EQ(w.x0 + w.x1, 16);
          ASSERT_EQ(w.y0 + w.y1, 16);
        }
      }
    }
  }
}

// One map per geometry, shared by later paddings; many geometries drop the cache rather
// than grow it, and a map still in use survives that.
TEST(CubePadding, BorderMapCacheIsSharedAndBounded) {
  using cube_padding_internal::cached_border_map;
  const std::shared_ptr<const cube_padding_internal::BorderMap> held = cached_border_map(2, 20, 16);
  EXPECT_EQ(cached_border_map(2, 20, 16), held);
  EXPECT_EQ(held->indices.size(), 52u * 52u - 20u * 20u);
  for (int n = 2; n <= 3 * static_cast<int>(cube_padding_internal::kMaxCachedBorderMaps); ++n) {
    cached_border_map(0, n, 8);
    EXPECT_LE(cube_padding_internal::cached_border_map_count(), cube_padding_internal::kMaxCachedBorderMaps);
  }
  const cube_padding_internal::BorderMap rebuilt = cube_padding_internal::build_border_map(2, 20, 16);
  EXPECT_EQ(held->indices, rebuilt.indices);
  EXPECT_TRUE(held->weights == rebuilt.weights);
}

// Threads padding more geometries than the cache holds, so that maps are built, shared
// and dropped under each other, still get the rule's samples.
TEST(CubePadding, ConcurrentPaddingMatchesThePerSampleRule) {
  std::mt19937 rng(77);
  std::vector<std::array<ImageYCbCr420, kFaceCount>> cubes;
  for (int n = 5; n <= 12; ++n) cubes.push_back(random_faces(n, rng));
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int round = 0; round < 3; ++round) {
        for (size_t c = 0; c < cubes.size(); ++c) {
          const int f = static_cast<int>((c + t + round) % kFaceCount), units = 1 + (t + round) % 2;
          ImageYCbCr420 padded;
          const ImageYCbCr420 expected = reference_padding(cubes[c], f, units);
          if (!pad_cube_face(pointers(cubes[c]), static_cast<Face>(f), units, &padded).ok() ||
              padded.y != expected.y || padded.cb != expected.cb || padded.cr != expected.cr) {
            ++mismatches;
          }
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(mismatches.load(), 0);
}

TEST(CubePadding, RejectsWhatItCannotPad) {
  std::array<ImageYCbCr420, kFaceCount> faces;
  for (int f = 0; f < kFaceCount; ++f) faces[f] = render_face(f, 32, environment);
  ImageYCbCr420 padded;
  padded.width = 5;
  const Status too_wide = pad_cube_face(pointers(faces), Face::kPX, kMaxCubeBorderUnits + 1, &padded);
  EXPECT_EQ(too_wide.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(too_wide.message().find("units"), std::string::npos) << too_wide.message();
  CubeFaces cube = pointers(faces);
  cube[static_cast<int>(Face::kPX)] = nullptr;
  const Status missing = pad_cube_face(cube, Face::kPX, 1, &padded);
  EXPECT_EQ(missing.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(missing.message().find("face px"), std::string::npos) << missing.message();
  faces[2] = render_face(2, 16, environment);
  EXPECT_EQ(pad_cube_face(pointers(faces), Face::kPX, 1, &padded).code(), ErrorCode::kInvalidArgument);
  ImageYCbCr420 wide = blank_face(32);
  wide.width = 48;
  faces[0] = wide;
  EXPECT_EQ(pad_cube_face(pointers(faces), Face::kPX, 1, &padded).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(padded.width, 5);  // untouched on error
}

// An adjacent face left out leaves 0 exactly where the rule reads that face, for every
// face, plane size (odd and even) and border; the rest is the full padding's.
TEST(CubePadding, FacesLeftOutLeaveZerosOnlyWhereTheyWouldBeRead) {
  for (int n : {16, 17}) {
    std::array<ImageYCbCr420, kFaceCount> faces;
    for (int f = 0; f < kFaceCount; ++f) faces[f] = render_face(f, n, textured_environment);
    for (int face = 0; face < kFaceCount; ++face) {
      ImageYCbCr420 full;
      ASSERT_TRUE(pad_cube_face(pointers(faces), static_cast<Face>(face), 1, &full).ok());
      for (int e = 0; e < kFaceEdgeCount; ++e) {
        const Face left_out = face_across(static_cast<Face>(face), static_cast<FaceEdge>(e));
        CubeFaces cube = pointers(faces);
        cube[static_cast<int>(left_out)] = nullptr;
        ImageYCbCr420 partial;
        ASSERT_TRUE(pad_cube_face(cube, static_cast<Face>(face), 1, &partial).ok());
        const int side = n + 2 * kCubeBorderUnitPixels;
        for (int j = 0; j < side; ++j) {
          for (int i = 0; i < side; ++i) {
            const int u = i - kCubeBorderUnitPixels, v = j - kCubeBorderUnitPixels;
            const bool inside = u >= 0 && v >= 0 && u < n && v < n;
            const bool from_left_out = !inside && cube_padding_internal::border_source(face, n, u, v).face ==
                                                      static_cast<int>(left_out);
            const size_t at = static_cast<size_t>(j) * side + i;
            ASSERT_EQ(partial.y[at], from_left_out ? 0 : full.y[at]) << face << " " << e << " " << i << "," << j;
          }
        }
      }
    }
  }
}

// border_edges_in_window against the rule itself: for every window of a small padded
// plane (odd and even sizes), the edges whose faces border_source names for some sample
// of the clamped window.
TEST(CubePadding, BorderEdgesInWindowMatchTheRuleSampleBySample) {
  for (int n : {5, 6}) {
    const int border = 3, last = n + 2 * border - 1;
    for (int y0 = -2; y0 <= last + 2; ++y0) {
      for (int y1 = y0; y1 <= last + 2; ++y1) {
        for (int x0 = -2; x0 <= last + 2; ++x0) {
          for (int x1 = x0; x1 <= last + 2; ++x1) {
            for (int face = 0; face < kFaceCount; face += 3) {
              uint8_t expected = 0;
              for (int y = std::clamp(y0, 0, last); y <= std::clamp(y1, 0, last); ++y) {
                for (int x = std::clamp(x0, 0, last); x <= std::clamp(x1, 0, last); ++x) {
                  const int u = x - border, v = y - border;
                  if (u >= 0 && v >= 0 && u < n && v < n) continue;
                  const int g = cube_padding_internal::border_source(face, n, u, v).face;
                  for (int e = 0; e < kFaceEdgeCount; ++e) {
                    if (static_cast<int>(face_across(static_cast<Face>(face), static_cast<FaceEdge>(e))) == g)
                      expected = static_cast<uint8_t>(expected | 1 << e);
                  }
                }
              }
              ASSERT_EQ(border_edges_in_window(n, border, x0, y0, x1, y1), expected)
                  << n << ": " << x0 << ".." << x1 << " x " << y0 << ".." << y1;
            }
          }
        }
      }
    }
  }
}

// Candidate per macroblock: where the centre of the macroblock of a camera turned by
// `yaw` lands on the reference face, in quarter pels (a direction, so depth plays no role).
FaceCandidates rotation_candidates(int face, int n, double yaw) {
  FaceCandidates candidates;
  const Vec right = cross(kForward[face], kUp[face]);
  for (int my = 0; my < n / 16; ++my) {
    for (int mx = 0; mx < n / 16; ++mx) {
      const double ci = 16 * mx + 7.5, cj = 16 * my + 7.5;
      const Vec d = pixel_direction(face, ci, cj, n, yaw);
      const double depth = dot(d, kForward[face]);
      const double x = dot(d, right) / depth, y = dot(d, kUp[face]) / depth;
      const double ri = (x + 1) * n / 2 - 0.5, rj = (1 - y) * n / 2 - 0.5;
      candidates.push_back({MotionVector{static_cast<int16_t>(std::lround(4 * (ri - ci))),
                                         static_cast<int16_t>(std::lround(4 * (rj - cj)))}});
    }
  }
  return candidates;
}

double psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double squared = 0;
  for (size_t i = 0; i < a.size(); ++i) squared += (double(a[i]) - double(b[i])) * (double(a[i]) - double(b[i]));
  return squared == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 * static_cast<double>(a.size()) / squared);
}

// A camera turned by 20 degrees sees, near one edge, what the reference cube shows on
// the adjacent face: with padded references those macroblocks are predicted from the
// border, and the face costs fewer bytes at no lower quality.
TEST(CubePadding, PaddedReferencesPredictContentFromTheAdjacentFace) {
  const int n = 64;
  const double yaw = 20 * 3.14159265358979 / 180;
  std::array<ImageYCbCr420, kFaceCount> faces;
  for (int f = 0; f < kFaceCount; ++f) faces[f] = render_face(f, n, textured_environment);
  const int face = static_cast<int>(Face::kPX);
  const ImageYCbCr420 source = render_face(face, n, textured_environment, yaw);
  const FaceCandidates candidates = rotation_candidates(face, n, yaw);
  ImageYCbCr420 padded;
  ASSERT_TRUE(pad_cube_face(pointers(faces), Face::kPX, 2, &padded).ok());
  BFrameParams params;
  params.qindex = 115;  // quantizer scale 6
  ImageYCbCr420 plain_recon, padded_recon, decoded;
  BFrameStats plain_stats, padded_stats;
  const std::vector<uint8_t> plain = encode_b_frame(source, faces[face], nullptr, candidate_hints(candidates, {}),
                                                    params, &plain_recon, &plain_stats);
  const std::vector<uint8_t> with_border = encode_b_frame(source, padded, nullptr, candidate_hints(candidates, {}),
                                                          params, &padded_recon, &padded_stats);
  ASSERT_FALSE(plain.empty());
  ASSERT_FALSE(with_border.empty());
  EXPECT_EQ(plain[kBFrameReferencesByte] & 7, 0);  // bits 0..2: the reference border
  EXPECT_EQ(with_border[kBFrameReferencesByte] & 7, 2);
  ASSERT_TRUE(decode_b_frame(with_border, n, n, padded, nullptr, &decoded).ok());
  EXPECT_EQ(decoded.y, padded_recon.y);
  EXPECT_EQ(decoded.cb, padded_recon.cb);
  EXPECT_EQ(decoded.cr, padded_recon.cr);
  EXPECT_GT(padded_stats.mb_leaving_face, 0);
  // Intra macroblocks are few on this small face either way (2 of 16 with either
  // reference since the context-modelled levels made them cheaper); never more.
  EXPECT_LE(padded_stats.mb_intra, plain_stats.mb_intra);
  EXPECT_LT(with_border.size(), plain.size());
  EXPECT_GE(psnr(padded_recon.y, source.y), psnr(plain_recon.y, source.y) - 0.5);
  // The bare face is refused for a payload coded against a padded one.
  EXPECT_EQ(decode_b_frame(with_border, n, n, faces[face], nullptr, &decoded).code(), ErrorCode::kInvalidArgument);

  // The border edges read: padded from the faces across them alone, the reference decodes
  // to the same pixels; with an edge read but not allowed, the payload is refused.
  BorderEdges edges;
  ASSERT_TRUE(decode_b_frame(with_border, n, n, padded, nullptr, &decoded, nullptr, nullptr, nullptr, &edges).ok());
  ASSERT_NE(edges.read[0], 0);
  EXPECT_EQ(edges.read[1], 0);
  CubeFaces cube = pointers(faces);
  for (int e = 0; e < kFaceEdgeCount; ++e) {
    if ((edges.read[0] >> e & 1) == 0)
      cube[static_cast<int>(face_across(Face::kPX, static_cast<FaceEdge>(e)))] = nullptr;
  }
  ImageYCbCr420 partly_padded, partly_decoded;
  ASSERT_TRUE(pad_cube_face(cube, Face::kPX, 2, &partly_padded).ok());
  BorderEdges allowed;
  allowed.allowed = edges.read;
  ASSERT_TRUE(decode_b_frame(with_border, n, n, partly_padded, nullptr, &partly_decoded, nullptr, nullptr, nullptr,
                             &allowed)
                  .ok());
  EXPECT_EQ(partly_decoded.y, padded_recon.y);
  EXPECT_EQ(partly_decoded.cb, padded_recon.cb);
  EXPECT_EQ(allowed.read, edges.read);
  const int first_read = std::countr_zero(static_cast<unsigned>(edges.read[0]));
  allowed.allowed[0] = static_cast<uint8_t>(edges.read[0] & ~(1 << first_read));
  const Status refused =
      decode_b_frame(with_border, n, n, padded, nullptr, &decoded, nullptr, nullptr, nullptr, &allowed);
  EXPECT_EQ(refused.code(), ErrorCode::kCorruptData);
  EXPECT_NE(refused.message().find("reads the cube border across edge " + std::to_string(first_read)),
            std::string::npos)
      << refused.message();
}

TEST(CubePadding, HeaderRejectsBordersBeyondTheLimit) {
  // Byte 2 bits 0-2: the border units (one reference, regular filter, no warp).
  std::vector<uint8_t> header = {kBidirectionalTypeBit | kBFrameSyntaxVersion, 10, kMaxCubeBorderUnits + 1, 0};
  BFrameHeader parsed;
  const Status status = parse_b_frame_header(header, &parsed);
  EXPECT_EQ(status.code(), ErrorCode::kCorruptData);
  EXPECT_NE(status.message().find("byte 2"), std::string::npos) << status.message();
  header[kBFrameReferencesByte] = kMaxCubeBorderUnits;
  ASSERT_TRUE(parse_b_frame_header(header, &parsed).ok());
  EXPECT_EQ(parsed.border_units, kMaxCubeBorderUnits);
}

}  // namespace
}  // namespace svc::codec
