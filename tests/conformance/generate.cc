// SPDX-License-Identifier: BSD-2-Clause
// svc-conformance-generate DIR [NAME...]: makes the conformance streams that DIR/streams
// does not hold yet (all of the table below, or the NAMEs given) and appends a line for
// each to DIR/streams.txt. A committed stream is never made again: the suite's streams
// are frozen, and this program only adds to them (docs/conformance.md). Each stream is a
// small scene encoded with the settings, and where needed the face pixels, that drive
// the encoder into the syntax it is there to cover.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "conformance/stream_digest.h"
#include "scene/scene.h"
#include "svc/encoder.h"

namespace svc::conformance {
namespace {

namespace fs = std::filesystem;
using samples::SceneKind;

// What replaces the rendered colour of every face. kChromaFromLuma: a texture whose
// chroma varies with its luma by a factor that steps from -2 to 2 in 1/8 from one
// macroblock to the next, which drives CfL through its whole range of alphas.
enum class Pixels { kRendered, kBlack, kWhite, kNoise, kStripes, kChromaFromLuma };

struct StreamSpec {
  std::string name;
  std::string what;
  samples::SceneOptions scene;
  std::function<void(EncoderSettings&)> settings = [](EncoderSettings&) {};
  Pixels pixels = Pixels::kRendered;
  std::string depth_mode;    // "radial" rewrites the manifest's depth mode
  int add_cells_from_x = 0;  // > 0: cells from this x on are added to the file by add_to_database
};

samples::SceneOptions scene(SceneKind kind, std::array<int, 3> grid, int face_size, uint32_t seed = 1) {
  samples::SceneOptions options;
  options.kind = kind;
  options.grid = grid;
  options.face_size = face_size;
  options.seed = seed;
  return options;
}

// A plaza whose cells stand 3 units apart: vectors reach far past the faces' edges.
samples::SceneOptions far_cells(int face_size) {
  samples::SceneOptions options = scene(SceneKind::kPlaza, {3, 1, 1}, face_size);
  options.spacing = {3.0, 1.0, 3.0};
  return options;
}

auto with_qindex(int qindex) {
  return [qindex](EncoderSettings& s) { s.qindex = qindex; };
}

auto without(std::vector<std::string> tools, std::function<void(EncoderSettings&)> more = {}) {
  return [tools, more](EncoderSettings& s) {
    for (const std::string& tool : tools) {
      if (!disable_coding_tool(&s.tools, tool).ok()) {
        std::fprintf(stderr, "no coding tool %s\n", tool.c_str());
        std::abort();
      }
    }
    if (more) more(s);
  };
}

std::vector<StreamSpec> stream_table();

std::array<uint8_t, 3> chroma_from_luma(int block, int x, int y) {
  const double alpha = (block % 33 - 16) / 8.0;
  const double texture = ((x * 7 + y * 13) % 17 - 8) * 5.0;
  const double luma = 128 + texture, cb = alpha * texture, cr = -alpha * texture;
  auto byte = [](double v) { return static_cast<uint8_t>(std::clamp(v + 0.5, 0.0, 255.0)); };
  return {byte(luma + 1.402 * cr), byte(luma - 0.344 * cb - 0.714 * cr), byte(luma + 1.772 * cb)};
}

// The colour of pixel (x, y) of the `face`-th face of the database (manifest order).
std::array<uint8_t, 3> pixel_rgb(Pixels pixels, int face, int x, int y, int blocks_x, std::mt19937& rng) {
  if (pixels == Pixels::kChromaFromLuma) return chroma_from_luma(face * 7 + (y / 16) * blocks_x + x / 16, x, y);
  std::array<uint8_t, 3> rgb{};
  for (int c = 0; c < 3; ++c) {
    switch (pixels) {
      case Pixels::kWhite: rgb[c] = 255; break;
      case Pixels::kNoise: rgb[c] = static_cast<uint8_t>(rng()); break;
      case Pixels::kStripes: rgb[c] = ((x / 2 + y / 3 + c) % 2) ? 255 : 0; break;
      default: break;  // kBlack; kRendered is never rewritten
    }
  }
  return rgb;
}

Status rewrite_pixels(const fs::path& db, Pixels pixels) {
  if (pixels == Pixels::kRendered) return Status();
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(db / "manifest.json"));
  const int w = manifest.at("face_size")[0], h = manifest.at("face_size")[1];
  std::mt19937 rng(7);
  int ordinal = 0;
  for (const auto& cell : manifest.at("cells")) {
    for (Face face : kAllFaces) {
      const fs::path path = db / cell.at("faces").at(face_name(face)).at("color").get<std::string>();
      std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3);
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          const auto value = pixel_rgb(pixels, ordinal, x, y, (w + 15) / 16, rng);
          std::copy(value.begin(), value.end(), rgb.begin() + (static_cast<ptrdiff_t>(y) * w + x) * 3);
        }
      }
      ++ordinal;
      auto out = OIIO::ImageOutput::create(path.string());
      if (!out || !out->open(path.string(), OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8)) ||
          !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !out->close()) {
        return Status(ErrorCode::kIoError, "cannot write " + path.string());
      }
    }
  }
  return Status();
}

// Rewrites the manifest of database `db` through `edit` (file errors throw, ending the run).
void edit_manifest(const fs::path& db, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json manifest = nlohmann::json::parse(std::ifstream(db / "manifest.json"));
  edit(manifest);
  std::ofstream(db / "manifest.json") << manifest.dump(2);
}

// A copy of `db` holding its cells with x < limit, for a first encode that
// add_to_database extends.
void copy_cells_below(const fs::path& db, const fs::path& part, int limit) {
  fs::copy(db, part, fs::copy_options::recursive);
  edit_manifest(part, [limit](nlohmann::json& manifest) {
    nlohmann::json kept = nlohmann::json::array();
    for (const auto& cell : manifest.at("cells")) {
      if (cell.at("index")[0].get<int>() < limit) kept.push_back(cell);
    }
    manifest["cells"] = kept;
  });
}

Status make_stream(const StreamSpec& spec, const fs::path& work, const fs::path& out) {
  const fs::path db = work / "db";
  SVC_RETURN_IF_ERROR(samples::generate_scene(spec.scene, db));
  SVC_RETURN_IF_ERROR(rewrite_pixels(db, spec.pixels));
  if (!spec.depth_mode.empty()) {
    edit_manifest(db, [&](nlohmann::json& manifest) { manifest["depth"] = spec.depth_mode; });
  }
  EncoderSettings settings = default_encoder_settings();
  settings.threads = 2;
  if (spec.settings) spec.settings(settings);
  const fs::path file = work / "stream.svc";
  if (spec.add_cells_from_x > 0) {
    copy_cells_below(db, work / "first", spec.add_cells_from_x);
    SVC_RETURN_IF_ERROR(encode_database(work / "first", file, settings).status());
    SVC_RETURN_IF_ERROR(add_to_database(file, db).status());
  } else {
    SVC_RETURN_IF_ERROR(encode_database(db, file, settings).status());
  }
  fs::rename(file, out);
  return Status();
}

int run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: svc-conformance-generate DIR [NAME...]\n");
    return 2;
  }
  const fs::path dir = argv[1];
  const std::set<std::string> wanted(argv + 2, argv + argc);
  fs::create_directories(dir / "streams");
  std::ofstream manifest(dir / "streams.txt", std::ios::app);
  int failures = 0;
  for (const StreamSpec& spec : stream_table()) {
    const fs::path out = dir / "streams" / (spec.name + ".svc");
    if ((!wanted.empty() && !wanted.count(spec.name)) || fs::exists(out)) continue;
    const fs::path work = fs::temp_directory_path() / ("svc-conformance-" + spec.name);
    fs::remove_all(work);
    fs::create_directories(work);
    Status made = make_stream(spec, work, out);
    fs::remove_all(work);
    Result<std::string> md5 = made.ok() ? stream_md5(out, DecodeSettings{}) : Result<std::string>(made);
    if (!md5.ok()) {
      std::fprintf(stderr, "%s: %s\n", spec.name.c_str(), md5.status().to_string().c_str());
      ++failures;
      continue;
    }
    manifest << spec.name << ' ' << *md5 << ' ' << spec.what << '\n';
    std::printf("%s %s (%ju bytes)\n", spec.name.c_str(), md5->c_str(), static_cast<uintmax_t>(fs::file_size(out)));
  }
  return failures == 0 ? 0 : 1;
}

std::vector<StreamSpec> stream_table() {
  std::vector<StreamSpec> t;
  t.push_back({"intra-q0", "I-faces only at quantizer index 0: the largest levels and their Exp-Golomb escapes",
               scene(SceneKind::kHall, {2, 1, 1}, 32), [](EncoderSettings& s) {
                 s.intra_only = true;
                 s.qindex = 0;
               }});
  t.push_back({"intra-q255",
               "I-faces only at quantizer index 255: the coarsest steps, nearly every block without levels",
               scene(SceneKind::kHall, {2, 1, 1}, 32), [](EncoderSettings& s) {
                 s.intra_only = true;
                 s.qindex = 255;
               }});
  t.push_back({"hall-default",
               "the default settings on a 3x1x3 hall: I- and B-cubes, visibility references, every tool",
               scene(SceneKind::kHall, {3, 1, 3}, 32)});
  t.push_back({"street-q20",
               "a fine quantizer (index 20) on a street of 48-pixel faces: many coded inter residuals",
               scene(SceneKind::kStreet, {3, 1, 2}, 48), with_qindex(20)});
  t.push_back({"plaza-q200", "a coarse quantizer (index 200) on a 64-pixel plaza: skips, large blocks",
               scene(SceneKind::kPlaza, {3, 1, 2}, 64), with_qindex(200)});
  t.push_back({"interior-36px",
               "36-pixel faces (not a multiple of 16): partial macroblocks at the right and bottom edges",
               scene(SceneKind::kInterior, {3, 1, 2}, 36)});
  t.push_back({"colonnade-20px", "20-pixel faces: one full and one 4-pixel macroblock column; chroma of 10",
               scene(SceneKind::kColonnade, {3, 1, 1}, 20)});
  t.push_back({"house-sparse", "a sparse grid (cells inside walls dropped) of rooms behind walls", [] {
                 auto o = scene(SceneKind::kHouse, {5, 1, 4}, 24);
                 o.sparse = true;
                 return o;
               }()});
  t.push_back({"hall-regular-layout", "the regular I-cube lattice with i-spacing 2x1x2 and the nearest references",
               scene(SceneKind::kHall, {4, 1, 3}, 32), [](EncoderSettings& s) {
                 s.layout = CubeLayout::kRegular;
                 s.i_spacing = {2, 1, 2};
               }});
  t.push_back({"street-log-search", "motion by logarithmic search instead of depth reprojection",
               scene(SceneKind::kStreet, {3, 1, 1}, 32),
               [](EncoderSettings& s) { s.motion = MotionSearch::kLogarithmic; }});
  t.push_back({"hall-two-layers", "a grid two cells high: references above and below",
               scene(SceneKind::kHall, {2, 2, 2}, 32)});
  t.push_back({"plaza-far-cells",
               "cells 3 units apart on 64-pixel faces: the largest vectors and cube-padding reaches",
               far_cells(64)});
  t.push_back({"black", "every pixel 0", scene(SceneKind::kHall, {3, 1, 1}, 32), {}, Pixels::kBlack});
  t.push_back({"white", "every pixel 255", scene(SceneKind::kHall, {3, 1, 1}, 32), {}, Pixels::kWhite});
  t.push_back({"noise-q0", "uniform noise at quantizer index 0: the largest residuals and clamps",
               scene(SceneKind::kHall, {2, 1, 1}, 16), with_qindex(0), Pixels::kNoise});
  t.push_back({"noise-q96", "uniform noise at quantizer index 96", scene(SceneKind::kHall, {3, 1, 1}, 16),
               with_qindex(96), Pixels::kNoise});
  t.push_back({"stripes", "full-contrast stripes: extreme edges for deblocking and CDEF",
               scene(SceneKind::kHall, {3, 1, 1}, 32), with_qindex(60), Pixels::kStripes});
  t.push_back({"depth-exact", "depth planes coded without error (maximum error 0)",
               scene(SceneKind::kHouse, {3, 1, 1}, 32), [](EncoderSettings& s) { s.depth = true; }});
  t.push_back({"depth-e12-radial", "depth planes with maximum error 12 from radial source depth",
               scene(SceneKind::kStreet, {3, 1, 2}, 32),
               [](EncoderSettings& s) {
                 s.depth = true;
                 s.depth_max_error = 12;
               },
               Pixels::kRendered, "radial"});
  t.push_back({"weighted-matrix", "the frequency-weighted quantization matrix and a B-face index offset of 0",
               scene(SceneKind::kInterior, {3, 1, 1}, 32), [](EncoderSettings& s) {
                 s.tools.weighted_quant_matrix = true;
                 s.b_qindex_offset = 0;
               }});
  t.push_back({"b-offset-max", "B-faces at the largest index offset from the I-faces' (quantizer index 255)",
               scene(SceneKind::kHall, {3, 1, 1}, 32), [](EncoderSettings& s) {
                 s.qindex = 100;
                 s.b_qindex_offset = 155;
               }});
  t.push_back({"no-loop-filters", "deblocking and CDEF off", scene(SceneKind::kStreet, {3, 1, 1}, 32),
               without({"deblocking", "cdef"})});
  t.push_back({"no-transform-tools", "DCT only (no transform types coded), 8x8 transforms only, no CfL",
               scene(SceneKind::kInterior, {3, 1, 1}, 32),
               without({"transform-types", "transform-sizes", "inter-transform-sizes", "cfl"})});
  t.push_back({"no-prediction-tools",
               "no warped prediction, one filter bank, half-pel, no cube references, median vector predictors, "
               "x/y vector differences",
               scene(SceneKind::kColonnade, {3, 1, 2}, 32),
               without({"warped-prediction", "switchable-filter", "quarter-pel", "cube-references",
                        "vector-predictors", "epipolar-lines"})});
  t.push_back({"no-intra-tools", "planar and DC only, in I-faces and B-face intra macroblocks",
               scene(SceneKind::kPlaza, {3, 1, 1}, 32), without({"intra-directional", "b-intra-prediction"})});
  t.push_back({"speed5", "the fastest speed's choices", scene(SceneKind::kStreet, {3, 1, 2}, 32),
               [](EncoderSettings& s) { (void)apply_encoder_speed(&s, kMaxEncoderSpeed); }});
  t.push_back({"daylight-antialiased", "a supersampled daylight render: antialiased edges, bright detail", [] {
                 auto o = scene(SceneKind::kStreet, {3, 1, 2}, 48, 3);
                 o.supersample = 2;
                 o.exposure_stops = 1.0;
                 return o;
               }()});
  t.push_back({"chroma-from-luma", "chroma that follows luma by factors from -2 to 2: CfL at every alpha",
               scene(SceneKind::kHall, {2, 1, 1}, 64), with_qindex(30), Pixels::kChromaFromLuma});
  for (int units = 1; units <= 3; ++units) {
    t.push_back({"cube-border-" + std::to_string(units),
                 "B-faces' references padded by " + std::to_string(units) +
                     " border unit(s) (--cube-border; the encoder's default is 4)",
                 scene(SceneKind::kHall, {3, 1, 2}, 32),
                 [units](EncoderSettings& s) { s.cube_border_units = units; }});
  }
  {
    StreamSpec added{"added-cells",
                     "cells appended by svc add: a second index, old I-cubes as new cells' references",
                     scene(SceneKind::kHall, {4, 1, 1}, 32)};
    added.add_cells_from_x = 2;
    t.push_back(added);
  }
  return t;
}

}  // namespace
}  // namespace svc::conformance

int main(int argc, char** argv) { return svc::conformance::run(argc, argv); }
