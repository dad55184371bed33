// SPDX-License-Identifier: BSD-2-Clause
// The frames svc-viewer should draw, computed on the CPU, and the comparison of two
// frames; tests/viewer_test.sh runs both.
//
//   svc-viewer-reference render FILE.svc --at X,Y,Z --look YAW,PITCH --size WxH --fov DEG
//                               [-o OUT.png] [--mirrored OUT.png] [--against FRAME.png]
//   svc-viewer-reference compare A.png B.png [--region X,Y,W,H]
//   svc-viewer-reference compare A.png B.png C.png D.png ...
//
// render: the frame of the cube map of the cell holding (X,Y,Z), seen from its centre as
// svc-viewer draws it without depth: every output pixel's ray (samples/viewer/view.h
// states the projection; it is written out again here, not shared) is looked up in the
// face whose camera axis is nearest, through that face's own view matrix and frustum,
// and filtered bilinearly; texels beyond the face's edge come from the face the
// direction of their centre falls on, as a seamless cube map filters across its edges.
// --mirrored also writes the frame of the faces mirrored left to right: faces in the
// wrong orientation, which the comparison must tell apart. --against compares FRAME with
// both, printing a line as compare does for each ("mirrored mean_abs ..." the second).
// compare: prints "mean_abs M p99 P max X psnr S" over the RGB samples of two frames of
// one size (a line for each pair of frames given), or of the rectangle --region gives (p99: the 99th percentile of
// the absolute differences, in 8-bit levels).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "svc/reader.h"

namespace {

using Vec = std::array<double, 3>;

Vec add(Vec a, Vec b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec scale(Vec a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec cross(Vec a, Vec b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec normalised(Vec a) { return scale(a, 1 / std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])); }

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

struct Face {
  svc::Camera camera;
  Image image;
};

// The rotation part of a column-major view matrix applied to a direction.
Vec rotate(const svc::Camera& c, Vec d) {
  const auto& m = c.world_to_camera;
  return {m[0] * d[0] + m[4] * d[1] + m[8] * d[2], m[1] * d[0] + m[5] * d[1] + m[9] * d[2],
          m[2] * d[0] + m[6] * d[1] + m[10] * d[2]};
}
// Its transpose: camera directions back to the world.
Vec unrotate(const svc::Camera& c, Vec e) {
  const auto& m = c.world_to_camera;
  return {m[0] * e[0] + m[1] * e[1] + m[2] * e[2], m[4] * e[0] + m[5] * e[1] + m[6] * e[2],
          m[8] * e[0] + m[9] * e[1] + m[10] * e[2]};
}

int face_seeing(const std::vector<Face>& faces, Vec d) {
  int best = 0;
  double best_cos = -2;
  for (int f = 0; f < 6; ++f) {
    const double c = -rotate(faces[f].camera, normalised(d))[2];
    if (c > best_cos) best_cos = c, best = f;
  }
  return best;
}

// Continuous pixel coordinates of direction d on face f (pixel (i, j) spans [i, i+1)).
std::array<double, 2> project(const Face& face, Vec d) {
  const Vec e = rotate(face.camera, d);
  const svc::Frustum& f = face.camera.frustum;
  const double x = e[0] * f.near_plane / -e[2], y = e[1] * f.near_plane / -e[2];
  return {(x - f.left) / (f.right - f.left) * face.image.width,
          (f.top - y) / (f.top - f.bottom) * face.image.height};
}

Vec unproject(const Face& face, double x, double y) {
  const svc::Frustum& f = face.camera.frustum;
  return unrotate(face.camera, {f.left + (f.right - f.left) * x / face.image.width,
                                f.top - (f.top - f.bottom) * y / face.image.height, -f.near_plane});
}

// Texel (i, j) of face f, which may lie beyond its edge: then the nearest texel of the
// face that sees the direction of its centre.
const uint8_t* texel(const std::vector<Face>& faces, int f, int i, int j) {
  const Image& image = faces[f].image;
  if (i < 0 || j < 0 || i >= image.width || j >= image.height) {
    const Vec d = unproject(faces[f], i + 0.5, j + 0.5);
    f = face_seeing(faces, d);
    const auto p = project(faces[f], d);
    i = std::clamp(static_cast<int>(std::floor(p[0])), 0, faces[f].image.width - 1);
    j = std::clamp(static_cast<int>(std::floor(p[1])), 0, faces[f].image.height - 1);
  }
  return &faces[f].image.rgb[(static_cast<size_t>(j) * faces[f].image.width + i) * 3];
}

std::array<uint8_t, 3> sample(const std::vector<Face>& faces, Vec d) {
  const int f = face_seeing(faces, d);
  const auto p = project(faces[f], d);
  const double x = p[0] - 0.5, y = p[1] - 0.5;
  const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
  const double fx = x - i, fy = y - j;
  const uint8_t *a = texel(faces, f, i, j), *b = texel(faces, f, i + 1, j);
  const uint8_t *c = texel(faces, f, i, j + 1), *e = texel(faces, f, i + 1, j + 1);
  std::array<uint8_t, 3> out{};
  for (int k = 0; k < 3; ++k) {
    const double v = (a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + e[k] * fx) * fy;
    out[k] = static_cast<uint8_t>(std::lround(v));
  }
  return out;
}

bool parse(const char* text, int count, char separator, double* out) {
  std::string s(text);
  for (int k = 0; k < count; ++k) {
    size_t used = 0;
    try {
      out[k] = std::stod(s, &used);
    } catch (...) {
      return false;
    }
    s = s.substr(used);
    if (k + 1 < count) {
      if (s.empty() || s[0] != separator) return false;
      s = s.substr(1);
    }
  }
  return s.empty();
}

std::optional<Image> read_png(const char* path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return std::nullopt;
  Image image;
  image.width = in->spec().width;
  image.height = in->spec().height;
  image.rgb.resize(static_cast<size_t>(image.width) * image.height * 3);
  if (in->spec().nchannels != 3 || !in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, image.rgb.data())) {
    return std::nullopt;
  }
  return image;
}

bool write_png(const char* path, const Image& image) {
  auto out = OIIO::ImageOutput::create(path);
  return out && out->open(path, OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::UINT8)) &&
         out->write_image(OIIO::TypeDesc::UINT8, image.rgb.data()) && out->close();
}

using Region = std::array<double, 4>;  // x, y, width, height

// Prints "mean_abs M p99 P max X psnr S" of the RGB samples of two frames of one size
// within `region`; false when there is nothing to compare.
bool print_difference(const char* label, const Image& a, const Image& b, const Region& r) {
  if (a.width != b.width || a.height != b.height) return false;
  std::vector<int> diff;
  double sum = 0, squares = 0;
  for (int y = std::max(0, static_cast<int>(r[1])); y < std::min(a.height, static_cast<int>(r[1] + r[3])); ++y) {
    for (int x = std::max(0, static_cast<int>(r[0])); x < std::min(a.width, static_cast<int>(r[0] + r[2])); ++x) {
      for (size_t k = (static_cast<size_t>(y) * a.width + x) * 3, c = 0; c < 3; ++c) {
        diff.push_back(std::abs(a.rgb[k + c] - b.rgb[k + c]));
        sum += diff.back();
        squares += static_cast<double>(diff.back()) * diff.back();
      }
    }
  }
  if (diff.empty()) return false;
  std::sort(diff.begin(), diff.end());
  const double mse = squares / diff.size();
  std::printf("%smean_abs %.3f p99 %d max %d psnr %.2f\n", label, sum / diff.size(), diff[diff.size() * 99 / 100],
              diff.back(), mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0);
  return true;
}

int compare(const char* a_path, const char* b_path, std::optional<Region> region) {
  const auto a = read_png(a_path), b = read_png(b_path);
  if (!a || !b || !print_difference("", *a, *b, region.value_or(Region{0, 0, 1.0 * a->width, 1.0 * a->height}))) {
    std::fprintf(stderr,
                 "svc-viewer-reference: cannot compare %s with %s (unreadable, sizes differ, or no pixel "
                 "in the region)\n",
                 a_path, b_path);
    return 1;
  }
  return 0;
}

struct RenderArgs {
  const char* input = nullptr;
  const char* output = nullptr;
  const char* mirrored_output = nullptr;
  const char* against = nullptr;
  double at[3] = {0, 0, 0}, look[2] = {0, 0}, size[2] = {0, 0}, fov = 0;
};

bool parse_render_args(int argc, char** argv, RenderArgs* r) {
  for (int k = 3; k + 1 < argc; k += 2) {
    const std::string arg = argv[k];
    const char* value = argv[k + 1];
    if (arg == "--at") {
      if (!parse(value, 3, ',', r->at)) return false;
    } else if (arg == "--look") {
      if (!parse(value, 2, ',', r->look)) return false;
    } else if (arg == "--size") {
      if (!parse(value, 2, 'x', r->size)) return false;
    } else if (arg == "--fov") {
      if (!parse(value, 1, ',', &r->fov)) return false;
    } else if (arg == "-o") {
      r->output = value;
    } else if (arg == "--mirrored") {
      r->mirrored_output = value;
    } else if (arg == "--against") {
      r->against = value;
    } else {
      return false;
    }
  }
  return argc % 2 == 1 && (r->output || r->against) && r->size[0] > 0 && r->size[1] > 0 && r->fov > 0;
}

std::optional<std::vector<Face>> load_faces(const RenderArgs& r) {
  auto reader = svc::Reader::open(r.input);
  if (!reader.ok()) return std::nullopt;
  const auto ordinal = (*reader)->find_cell_at({r.at[0], r.at[1], r.at[2]});
  if (!ordinal) return std::nullopt;
  const svc::CellEntry& cell = (*reader)->cells()[*ordinal];
  auto cube = (*reader)->decode_cube(cell.index);
  if (!cube.ok()) return std::nullopt;
  std::vector<Face> faces(6);
  for (int f = 0; f < 6; ++f)
    faces[f] = {cell.cameras[f], {(*cube)[f].width, (*cube)[f].height, (*cube)[f].pixels}};
  return faces;
}

void mirror(std::vector<Face>* faces) {
  for (Face& face : *faces) {
    Image& image = face.image;
    for (int y = 0; y < image.height; ++y) {
      uint8_t* row = &image.rgb[static_cast<size_t>(y) * image.width * 3];
      for (int x = 0; x < image.width / 2; ++x)
        std::swap_ranges(row + x * 3, row + x * 3 + 3, row + (image.width - 1 - x) * 3);
    }
  }
}

// The frame through the viewer's projection (samples/viewer/view.h).
Image render_frame(const std::vector<Face>& faces, const RenderArgs& r) {
  const double yaw = r.look[0] * std::numbers::pi / 180, pitch = r.look[1] * std::numbers::pi / 180;
  const Vec forward = {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
  const Vec right = normalised(cross(forward, {0, 1, 0}));
  const Vec up = cross(right, forward);
  Image frame{static_cast<int>(r.size[0]), static_cast<int>(r.size[1]), {}};
  frame.rgb.resize(static_cast<size_t>(frame.width) * frame.height * 3);
  const double tan_half = std::tan(r.fov * std::numbers::pi / 360), aspect = r.size[0] / r.size[1];
  for (int j = 0; j < frame.height; ++j) {
    for (int i = 0; i < frame.width; ++i) {
      const double x = (2 * (i + 0.5) / frame.width - 1) * tan_half * aspect;
      const double y = (1 - 2 * (j + 0.5) / frame.height) * tan_half;
      const auto rgb = sample(faces, add(forward, add(scale(right, x), scale(up, y))));
      std::memcpy(&frame.rgb[(static_cast<size_t>(j) * frame.width + i) * 3], rgb.data(), 3);
    }
  }
  return frame;
}

// Writes or compares the CPU's frame and the frame of mirrored faces.
bool deliver(const char* output, const char* label, const Image& frame, const std::optional<Image>& against) {
  if (output && !write_png(output, frame)) return false;
  return !against || print_difference(label, *against, frame, Region{0, 0, 1.0 * frame.width, 1.0 * frame.height});
}

int render(int argc, char** argv) {
  RenderArgs r;
  r.input = argc > 2 ? argv[2] : nullptr;
  if (!parse_render_args(argc, argv, &r)) {
    std::fprintf(stderr,
                 "svc-viewer-reference: render FILE.svc --at X,Y,Z --look YAW,PITCH --size WxH --fov DEG "
                 "[-o OUT.png] [--mirrored OUT.png] [--against FRAME.png]\n");
    return 2;
  }
  auto faces = load_faces(r);
  std::optional<Image> against;
  if (r.against && !(against = read_png(r.against))) {
    std::fprintf(stderr, "svc-viewer-reference: cannot read %s\n", r.against);
    return 1;
  }
  if (!faces) {
    std::fprintf(stderr, "svc-viewer-reference: cannot decode the cell at the eye from %s\n", r.input);
    return 1;
  }
  bool ok = deliver(r.output, "", render_frame(*faces, r), against);
  if (ok && (r.mirrored_output || against)) {
    mirror(&*faces);
    ok = deliver(r.mirrored_output, "mirrored ", render_frame(*faces, r), against);
  }
  if (!ok) {
    std::fprintf(stderr, "svc-viewer-reference: cannot write or compare the frames\n");
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "render") == 0) return render(argc, argv);
  if (argc >= 4 && std::strcmp(argv[1], "compare") == 0) {
    std::array<double, 4> region{};
    if (argc == 6 && std::strcmp(argv[4], "--region") == 0 && parse(argv[5], 4, ',', region.data())) {
      return compare(argv[2], argv[3], region);
    }
    for (int k = 2; argc % 2 == 0 && k < argc; k += 2) {
      if (const int status = compare(argv[k], argv[k + 1], std::nullopt)) return status;
    }
    if (argc % 2 == 0) return 0;
  }
  std::fprintf(stderr, "usage: svc-viewer-reference render ... | compare A.png B.png [--region X,Y,W,H]\n");
  return 2;
}
