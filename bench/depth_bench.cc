// SPDX-License-Identifier: BSD-2-Clause
// Depth beside color: the bytes of every face's depth of a database stored by svc and by
// general image and video coders, side by side in one run (docs/bench.md, "Depth beside
// color"):
//
//   build/bin/svc-bench-depth DB [DB...] [--max-error 8] [--threads N] [--keep DIR [--reuse-svc]]
//
// Every coder gets the same planes: each face's inverse-depth codes (docs/codec.md 8.1,
// c = round(65535 near / z) clamped to 1..65535, 0 without geometry), from the database's
// depth files and cameras.
//   svc      `encode_database` at quality 50 with depth at maximum error 0 and at E
//            (FileInfo::depth_bytes of the written file, and its share of the file), and
//            once without depth (the color-only file, for reference). Each file's depth is
//            decoded again and checked against the source codes (E = 0: equal; E: within
//            E, background exact); a failed check prints FAIL instead of the bytes.
//   PNG16    one 16-bit greyscale PNG a face, the codes as they are (OpenImageIO, zlib
//            level 9). Lossless.
//   JXL      `cjxl IN.png OUT.jxl -d 0 -e 7` of each PNG (lossless; checked with djxl).
//   AV1      not applicable at E = 0: lossless AV1 holds at most 12 bits a sample.
// With --max-error 8, the same coders on 12-bit codes q = c == 0 ? 0 : max(1, (c + 8) >> 4)
// (capped at 4095), reconstructed as min(65535, 16 q): within 8 of c (except the capped
// codes above 65527, whose error the run reports):
//   PNG12    the q as 16-bit PNG; JXL12 those PNGs through cjxl;
//   AV1      per face direction, the cells' faces in manifest order as one video through
//            ffmpeg's libaom-av1, gray12le, lossless=1, cpu-used 4, row-mt 1, lag-in-frames 0
//            (decoded again and compared); the six .ivf files' bytes, IVF framing included (a
//            32-byte header and 12 bytes a frame). Streams that do not decode to their
//            frames are marked and their differences counted. (With libaom 3.6's default
//            lookahead, lossless=1 alone decoded with samples up to 8 off on the corpus
//            scenes; without lookahead, lag-in-frames 0, the streams decode exactly.)
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <CLI/CLI.hpp>

#include "codec/encoder/depth_encoder.h"
#include "common/parallel.h"
#include "database/database.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace {

using namespace svc;
namespace fs = std::filesystem;

constexpr int kQuantizedShift = 4;  // 16-bit codes to 12-bit ones
constexpr uint16_t kMaxQuantized = 4095;

// Every face's inverse-depth codes of one database, in manifest cell order, six faces a
// cell in Face order.
struct SceneCodes {
  std::string name;
  int width = 0, height = 0;
  std::vector<CellIndex> cells;
  std::vector<std::vector<uint16_t>> faces;  // cell * 6 + face
};

uint16_t quantized(uint16_t c) {
  if (c == 0) return 0;
  return static_cast<uint16_t>(std::min<int>(kMaxQuantized, std::max(1, (c + 8) >> kQuantizedShift)));
}

int dequantized(uint16_t q) { return std::min(65535, q << kQuantizedShift); }

Result<SceneCodes> load_codes(const fs::path& db, int threads) {
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db));
  SceneCodes scene;
  scene.name = fs::absolute(db).lexically_normal().filename().string();
  if (scene.name.empty()) scene.name = fs::absolute(db).lexically_normal().parent_path().filename().string();
  scene.width = manifest.face_width;
  scene.height = manifest.face_height;
  scene.cells.resize(manifest.cells.size());
  scene.faces.resize(manifest.cells.size() * kFaceCount);
  SVC_RETURN_IF_ERROR(parallel_for(manifest.cells.size(), threads, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(CellSource cell, read_cell(manifest, i));
    scene.cells[i] = cell.index;
    for (Face face : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(std::vector<float> depth, load_face_depth(manifest, cell, face));
      const double near_plane = cell.faces[static_cast<int>(face)].camera.frustum.near_plane;
      scene.faces[i * kFaceCount + static_cast<int>(face)] = codec::inverse_depth_codes(depth, near_plane);
    }
    return Status::Ok();
  }));
  return scene;
}

std::string quoted(const fs::path& p) {
  std::string out = "'";
  for (char ch : p.string()) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

Status run(const std::string& command) {
  const int rc = std::system((command + " >/dev/null 2>&1").c_str());
  if (rc != 0 || !WIFEXITED(rc) || WEXITSTATUS(rc) != 0) {
    return Status(ErrorCode::kInternal, "command failed (" + std::to_string(rc) + "): " + command);
  }
  return Status::Ok();
}

bool have_program(const char* name) {
  return std::system((std::string("command -v ") + name + " >/dev/null 2>&1").c_str()) == 0;
}

uint64_t file_bytes(const fs::path& p) { return fs::file_size(p); }

std::string face_file(const SceneCodes& scene, size_t k, const char* ext) {
  const CellIndex& c = scene.cells[k / kFaceCount];
  return "cell_" + std::to_string(c.x) + "_" + std::to_string(c.y) + "_" + std::to_string(c.z) + "_" +
         face_name(kAllFaces[k % kFaceCount]) + ext;
}

Status write_png16(const fs::path& path, const std::vector<uint16_t>& plane, int width, int height) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) return Status(ErrorCode::kIoError, "no PNG writer for " + path.string());
  OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::UINT16);
  spec.attribute("compression", "zip:9");
  spec.attribute("png:compressionLevel", 9);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT16, plane.data()) || !out->close()) {
    return Status(ErrorCode::kIoError, "writing " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

Result<std::vector<uint16_t>> read_png16(const fs::path& path, int width, int height) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return Status(ErrorCode::kIoError, "reading " + path.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width != width || spec.height != height) {
    return Status(ErrorCode::kCorruptData, path.string() + ": wrong size");
  }
  std::vector<uint16_t> pixels(static_cast<size_t>(width) * height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT16, pixels.data())) {
    return Status(ErrorCode::kIoError, "reading " + path.string() + ": " + in->geterror());
  }
  std::vector<uint16_t> plane(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < plane.size(); ++i) plane[i] = pixels[i * spec.nchannels];
  return plane;
}

// One plane set (the codes or their 12-bit quantization) as PNG and JXL.
struct ImageBytes {
  uint64_t png = 0, jxl = 0;
  bool jxl_done = false;
};

// Writes every face of `planes` as 16-bit PNG under `dir` and, with `jxl`, through cjxl,
// each JXL decoded again by djxl and compared with its plane.
Result<ImageBytes> code_images(const SceneCodes& scene, const std::vector<std::vector<uint16_t>>& planes,
                               const fs::path& dir, bool jxl, int threads) {
  fs::create_directories(dir);
  std::atomic<uint64_t> png{0}, jxl_bytes{0};
  SVC_RETURN_IF_ERROR(parallel_for(planes.size(), threads, [&](size_t k) -> Status {
    const fs::path png_path = dir / face_file(scene, k, ".png");
    SVC_RETURN_IF_ERROR(write_png16(png_path, planes[k], scene.width, scene.height));
    SVC_ASSIGN_OR_RETURN(std::vector<uint16_t> back, read_png16(png_path, scene.width, scene.height));
    if (back != planes[k]) return Status(ErrorCode::kInternal, png_path.string() + " does not read back");
    png += file_bytes(png_path);
    if (!jxl) return Status::Ok();
    const fs::path jxl_path = dir / face_file(scene, k, ".jxl");
    const fs::path decoded = dir / face_file(scene, k, ".djxl.png");
    SVC_RETURN_IF_ERROR(
        run("cjxl " + quoted(png_path) + " " + quoted(jxl_path) + " -d 0 -e 7 --num_threads=0 --quiet"));
    SVC_RETURN_IF_ERROR(run("djxl " + quoted(jxl_path) + " " + quoted(decoded) + " --num_threads=0"));
    SVC_ASSIGN_OR_RETURN(std::vector<uint16_t> dec, read_png16(decoded, scene.width, scene.height));
    if (dec != planes[k]) return Status(ErrorCode::kInternal, jxl_path.string() + " does not decode losslessly");
    fs::remove(decoded);
    jxl_bytes += file_bytes(jxl_path);
    return Status::Ok();
  }));
  return ImageBytes{png.load(), jxl_bytes.load(), jxl};
}

// AV1 of the 12-bit planes, asked for lossless: the six streams' bytes, and what decoding
// them again gives back: the samples that differ from the frames coded and the largest
// difference (both 0 when the streams are lossless).
struct Av1Bytes {
  uint64_t bytes = 0;
  uint64_t wrong_samples = 0;
  int max_error = 0;  // in 12-bit code units
};

// One gray12le video per face direction, its frames the cells' faces in manifest order;
// each stream decoded again by ffmpeg and compared with its frames.
Result<Av1Bytes> code_av1(const SceneCodes& scene, const std::vector<std::vector<uint16_t>>& planes,
                          const fs::path& dir, int threads) {
  fs::create_directories(dir);
  std::atomic<uint64_t> bytes{0}, wrong{0};
  std::atomic<int> worst{0};
  const std::string size = std::to_string(scene.width) + "x" + std::to_string(scene.height);
  SVC_RETURN_IF_ERROR(parallel_for(kFaceCount, threads, [&](size_t f) -> Status {
    const std::string name = face_name(kAllFaces[f]);
    const fs::path raw = dir / (name + ".gray12le"), ivf = dir / (name + ".ivf"),
                   decoded = dir / (name + ".decoded.gray12le");
    std::vector<uint8_t> frames;
    for (size_t cell = 0; cell < scene.cells.size(); ++cell) {
      for (uint16_t q : planes[cell * kFaceCount + f]) {
        frames.push_back(static_cast<uint8_t>(q & 0xff));
        frames.push_back(static_cast<uint8_t>(q >> 8));
      }
    }
    {
      std::ofstream out(raw, std::ios::binary);
      out.write(reinterpret_cast<const char*>(frames.data()), static_cast<std::streamsize>(frames.size()));
      if (!out) return Status(ErrorCode::kIoError, "writing " + raw.string());
    }
    SVC_RETURN_IF_ERROR(run("ffmpeg -nostdin -v error -y -f rawvideo -pix_fmt gray12le -s " + size +
                            " -framerate 25 -i " + quoted(raw) +
                            " -c:v libaom-av1 -pix_fmt gray12le -aom-params lossless=1 -cpu-used 4 -row-mt 1"
                            " -lag-in-frames 0 -threads 1 " +
                            quoted(ivf)));
    SVC_RETURN_IF_ERROR(
        run("ffmpeg -nostdin -v error -y -i " + quoted(ivf) + " -f rawvideo -pix_fmt gray12le " + quoted(decoded)));
    std::ifstream in(decoded, std::ios::binary);
    std::vector<uint8_t> back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (back.size() != frames.size())
      return Status(ErrorCode::kInternal, ivf.string() + " decodes to another size");
    for (size_t i = 0; i < frames.size(); i += 2) {
      const int a = frames[i] | frames[i + 1] << 8, b = back[i] | back[i + 1] << 8;
      if (a == b) continue;
      ++wrong;
      for (int w = worst.load(); std::abs(a - b) > w && !worst.compare_exchange_weak(w, std::abs(a - b));) {
      }
    }
    fs::remove(raw);
    fs::remove(decoded);
    bytes += file_bytes(ivf);
    return Status::Ok();
  }));
  return Av1Bytes{bytes.load(), wrong.load(), worst.load()};
}

struct SvcFile {
  uint64_t file_bytes = 0;
  uint64_t depth_bytes = 0;
  int measured_error = -1;         // largest |decoded - source| over geometry pixels
  uint64_t background_errors = 0;  // pixels where exactly one of decoded and source is 0
  bool ok = false;
  std::string problem;
};

// Encodes `db` into `out` (unless `reuse` and `out` exists) and checks its depth.
Result<SvcFile> encode_svc(const fs::path& db, const fs::path& out, int threads, bool depth, int max_error,
                           const SceneCodes& scene, bool reuse) {
  EncoderSettings settings = default_encoder_settings();
  settings.quality = 50;
  settings.threads = threads;
  settings.depth = depth;
  settings.depth_max_error = max_error;
  if (!reuse || !fs::exists(out)) SVC_RETURN_IF_ERROR(encode_database(db, out, settings).status());
  ReaderSettings reader_settings = default_reader_settings();
  reader_settings.prefetch_threads = 0;
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(out, reader_settings));
  SvcFile result;
  result.file_bytes = reader->info().file_bytes;
  result.depth_bytes = reader->info().depth_bytes;
  if (!depth) {
    result.ok = true;
    return result;
  }
  if (!reader->info().has_depth) return Status(ErrorCode::kInternal, out.string() + " holds no depth");
  std::vector<uint16_t> decoded(static_cast<size_t>(scene.width) * scene.height);
  int worst = 0;
  for (size_t k = 0; k < scene.faces.size(); ++k) {
    DepthBuffer buffer;
    buffer.format = DepthFormat::kInverse16;
    buffer.data = decoded.data();
    buffer.stride = static_cast<size_t>(scene.width) * 2;
    buffer.size = decoded.size() * 2;
    Status status = reader->decode_face_depth_into(scene.cells[k / kFaceCount], kAllFaces[k % kFaceCount], buffer);
    if (!status.ok()) {
      result.problem = "decoding " + face_file(scene, k, "") + ": " + status.to_string();
      return result;
    }
    const std::vector<uint16_t>& source = scene.faces[k];
    for (size_t i = 0; i < decoded.size(); ++i) {
      if ((source[i] == 0) != (decoded[i] == 0)) {
        ++result.background_errors;
        continue;
      }
      worst = std::max(worst, std::abs(static_cast<int>(decoded[i]) - static_cast<int>(source[i])));
    }
  }
  result.measured_error = worst;
  result.ok = worst <= max_error && result.background_errors == 0;
  if (!result.ok) {
    result.problem = "decoded depth off by " + std::to_string(worst) + " (allowed " + std::to_string(max_error) +
                     "), " + std::to_string(result.background_errors) + " background pixels wrong";
  }
  return result;
}

struct SceneResult {
  std::string name;
  size_t faces = 0;
  SvcFile color, lossless, lossy;
  ImageBytes images16, images12;
  std::optional<Av1Bytes> av1;
  int quantized_error = 0;     // largest |min(65535, 16 q) - c| over geometry pixels
  uint64_t capped_pixels = 0;  // codes above 65527, whose q was capped at 4095
};

std::string bytes_or_fail(const SvcFile& f) { return f.ok ? std::to_string(f.depth_bytes) : std::string("FAIL"); }

// AV1's bytes, marked with * when its streams did not decode to the frames coded.
std::string av1_cell(const std::optional<Av1Bytes>& a) {
  if (!a) return "-";
  return std::to_string(a->bytes) + (a->wrong_samples > 0 ? "*" : "");
}

std::string share(const SvcFile& f) {
  if (!f.ok || f.file_bytes == 0) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * static_cast<double>(f.depth_bytes) / f.file_bytes);
  return text;
}

Result<SceneResult> measure(const fs::path& db, const fs::path& work, int max_error, int threads, bool jxl,
                            bool av1, bool reuse) {
  SVC_ASSIGN_OR_RETURN(SceneCodes scene, load_codes(db, threads));
  SceneResult r;
  r.name = scene.name;
  r.faces = scene.faces.size();
  const fs::path dir = work / scene.name;
  fs::create_directories(dir);
  std::fprintf(stderr, "%s: %zu faces of %dx%d\n", scene.name.c_str(), r.faces, scene.width, scene.height);

  std::fprintf(stderr, "  svc color only\n");
  SVC_ASSIGN_OR_RETURN(r.color, encode_svc(db, dir / "color.svc", threads, false, 0, scene, reuse));
  std::fprintf(stderr, "  svc depth E=0\n");
  SVC_ASSIGN_OR_RETURN(r.lossless, encode_svc(db, dir / "depth-e0.svc", threads, true, 0, scene, reuse));
  std::fprintf(stderr, "  svc depth E=%d\n", max_error);
  SVC_ASSIGN_OR_RETURN(r.lossy, encode_svc(db, dir / ("depth-e" + std::to_string(max_error) + ".svc"), threads,
                                           true, max_error, scene, reuse));

  std::fprintf(stderr, "  PNG16%s\n", jxl ? ", JXL" : "");
  SVC_ASSIGN_OR_RETURN(r.images16, code_images(scene, scene.faces, dir / "png16", jxl, threads));
  if (max_error == 8) {
    std::vector<std::vector<uint16_t>> q(scene.faces.size());
    for (size_t k = 0; k < q.size(); ++k) {
      q[k].resize(scene.faces[k].size());
      for (size_t i = 0; i < q[k].size(); ++i) {
        const uint16_t c = scene.faces[k][i];
        q[k][i] = quantized(c);
        if (c == 0) continue;
        if (c > 65527) ++r.capped_pixels;
        r.quantized_error = std::max(r.quantized_error, std::abs(dequantized(q[k][i]) - c));
      }
    }
    std::fprintf(stderr, "  PNG12%s\n", jxl ? ", JXL12" : "");
    SVC_ASSIGN_OR_RETURN(r.images12, code_images(scene, q, dir / "png12", jxl, threads));
    if (av1) {
      std::fprintf(stderr, "  AV1 gray12 lossless\n");
      SVC_ASSIGN_OR_RETURN(r.av1, code_av1(scene, q, dir / "av1", threads));
    }
  }
  return r;
}

void print_table(const std::vector<SceneResult>& results, int max_error, bool jxl, bool av1) {
  std::printf("\nDepth bytes of all faces (inverse-depth codes, docs/codec.md 8.1)\n");
  std::printf("%-12s %6s %10s | %10s %10s %10s %10s | %10s", "scene", "faces", "color-only", "svc E=0", "PNG16",
              "JXL", "AV1", ("svc E=" + std::to_string(max_error)).c_str());
  if (max_error == 8) std::printf(" %10s %10s %10s", "PNG12", "JXL12", "AV1 gray12");
  std::printf(" | %7s %7s\n", "share 0", ("share " + std::to_string(max_error)).c_str());
  auto cell = [](bool present, uint64_t v) { return present ? std::to_string(v) : std::string("-"); };
  auto print_row = [&](const std::string& label, const SceneResult& r) {
    std::printf("%-12s %6zu %10llu | %10s %10llu %10s %10s | %10s", label.c_str(), r.faces,
                static_cast<unsigned long long>(r.color.file_bytes), bytes_or_fail(r.lossless).c_str(),
                static_cast<unsigned long long>(r.images16.png), cell(jxl, r.images16.jxl).c_str(), "n/a",
                bytes_or_fail(r.lossy).c_str());
    if (max_error == 8) {
      std::printf(" %10llu %10s %10s", static_cast<unsigned long long>(r.images12.png),
                  cell(jxl, r.images12.jxl).c_str(), av1_cell(r.av1).c_str());
    }
    std::printf(" | %7s %7s\n", share(r.lossless).c_str(), share(r.lossy).c_str());
  };
  SceneResult total;
  total.name = "total";
  bool all_ok0 = true, all_ok = true;
  for (const SceneResult& r : results) {
    print_row(r.name.substr(0, r.name.find('-')), r);
    total.faces += r.faces;
    total.color.file_bytes += r.color.file_bytes;
    total.lossless.depth_bytes += r.lossless.depth_bytes;
    total.lossless.file_bytes += r.lossless.file_bytes;
    total.lossy.depth_bytes += r.lossy.depth_bytes;
    total.lossy.file_bytes += r.lossy.file_bytes;
    total.images16.png += r.images16.png;
    total.images16.jxl += r.images16.jxl;
    total.images12.png += r.images12.png;
    total.images12.jxl += r.images12.jxl;
    if (r.av1) {
      Av1Bytes sum = total.av1.value_or(Av1Bytes{});
      sum.bytes += r.av1->bytes;
      sum.wrong_samples += r.av1->wrong_samples;
      sum.max_error = std::max(sum.max_error, r.av1->max_error);
      total.av1 = sum;
    }
    all_ok0 = all_ok0 && r.lossless.ok;
    all_ok = all_ok && r.lossy.ok;
  }
  if (results.size() > 1) {
    total.lossless.ok = all_ok0;
    total.lossy.ok = all_ok;
    print_row("total", total);
  }

  std::printf("\nAV1 n/a at E=0: lossless AV1 holds at most 12 bits a sample, the codes take 16.\n");
  std::printf("color-only: the .svc file without depth (quality 50); share: depth bytes / file bytes.\n");
  if (max_error == 8) {
    std::printf(
        "PNG12, JXL12, AV1 gray12: codes q = c == 0 ? 0 : min(4095, max(1, (c + 8) >> 4)), reconstructed "
        "as min(65535, 16 q): within 8 of c for every c <= 65527.\n");
    if (av1) {
      std::printf(
          "AV1 gray12: ffmpeg libaom-av1 -pix_fmt gray12le -aom-params lossless=1 -cpu-used 4 -row-mt 1 "
          "-lag-in-frames 0, one stream per face direction (cells in manifest order, libaom's keyframe "
          "placement); "
          "bytes of the six .ivf files, IVF framing included (32 bytes a file, 12 a frame).\n");
      std::printf(
          "AV1 *: the streams, decoded again by ffmpeg, differ from the 12-bit frames coded (counts below): "
          "not lossless despite lossless=1.\n");
    }
  } else {
    std::printf("PNG12, JXL12 and AV1 gray12 (the equal-error comparison at E = 8) only with --max-error 8.\n");
  }
  std::printf(
      "\nMeasured maximum error of decoded codes against the source codes (geometry pixels; background "
      "checked exact):\n");
  for (const SceneResult& r : results) {
    const std::string label = r.name.substr(0, r.name.find('-'));
    std::printf("  %-12s svc E=0: %d%s   svc E=%d: %d%s", label.c_str(), r.lossless.measured_error,
                r.lossless.ok ? "" : (" FAIL: " + r.lossless.problem).c_str(), max_error, r.lossy.measured_error,
                r.lossy.ok ? "" : (" FAIL: " + r.lossy.problem).c_str());
    if (max_error == 8) {
      std::printf("   12-bit codes: %d (%llu codes above 65527)", r.quantized_error,
                  static_cast<unsigned long long>(r.capped_pixels));
    }
    if (r.av1) {
      std::printf("   AV1 decoded: %llu samples differ, by up to %d",
                  static_cast<unsigned long long>(r.av1->wrong_samples), r.av1->max_error);
    }
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Bytes of every face's depth: svc against 16-bit PNG, lossless JPEG XL and lossless AV1"};
  std::vector<std::string> databases;
  int max_error = 8;
  int threads = 0;
  std::string keep;
  app.add_option("databases", databases, "svc-input database folders")->required();
  app.add_option("--max-error", max_error, "svc's depth maximum error for the second column set")
      ->check(CLI::Range(0, codec::kMaxDepthError));
  app.add_option("--threads", threads, "worker threads (0: all)")->check(CLI::NonNegativeNumber);
  app.add_option("--keep", keep, "keep every coded file under this folder (default: a temporary one, removed)");
  bool reuse = false;
  app.add_flag("--reuse-svc", reuse,
               "with --keep: take the .svc files an earlier run left there rather than encoding again "
               "(their depth is checked all the same)");
  CLI11_PARSE(app, argc, argv);
  threads = resolve_thread_count(threads);

  configure_image_loading();
  const bool jxl = have_program("cjxl") && have_program("djxl");
  const bool av1 = have_program("ffmpeg");
  if (!jxl) std::printf("cjxl or djxl not found (Debian: libjxl-tools): the JXL columns are skipped.\n");
  if (!av1) std::printf("ffmpeg not found: the AV1 column is skipped.\n");

  fs::path work;
  if (!keep.empty()) {
    work = keep;
  } else {
    work = fs::temp_directory_path() / ("svc-bench-depth-" + std::to_string(getpid()));
  }
  fs::create_directories(work);

  std::vector<SceneResult> results;
  int rc = 0;
  for (const std::string& db : databases) {
    Result<SceneResult> r = measure(db, work, max_error, threads, jxl, av1, reuse);
    if (!r.ok()) {
      std::fprintf(stderr, "%s: %s\n", db.c_str(), r.status().to_string().c_str());
      rc = 1;
      continue;
    }
    if (!r->lossless.ok || !r->lossy.ok) rc = 1;
    results.push_back(std::move(*r));
  }
  std::printf("svc-bench-depth --max-error %d --threads %d\n", max_error, threads);
  for (const std::string& db : databases) std::printf("  %s\n", db.c_str());
  print_table(results, max_error, jxl, av1);
  if (keep.empty()) fs::remove_all(work);
  return rc;
}
