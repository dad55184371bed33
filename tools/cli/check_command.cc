// svc check: validates a database as the encoder reads it (manifest, every image's size,
// channels and depth) without encoding, and summarises it.
#include <cmath>
#include <cstdio>
#include <mutex>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/command_line.h"
#include "common/parallel.h"
#include "database/database.h"

namespace svc::cli {

namespace {

struct CheckResult {
  std::vector<std::string> problems;  // one per face that the encoder would refuse, in order
  uint64_t faces = 0;                 // faces that load
  uint64_t pixels = 0;                // in the faces that load
  uint64_t background_pixels = 0;     // of those, pixels whose depth saw no geometry
};

struct FaceCheck {
  Status status;
  uint64_t pixels = 0;
  uint64_t background = 0;
};

Result<CheckResult> check_faces(const DatabaseManifest& manifest, const CheckOptions& options) {
  const size_t total = manifest.cells.size() * kFaceCount;
  std::vector<FaceCheck> checks(total);
  std::mutex progress_mutex;
  uint64_t done = 0;
  ProgressBar bar("checking", options.verbosity.show_progress());
  SVC_RETURN_IF_ERROR(parallel_for(total, resolve_thread_count(options.threads), [&](size_t i) -> Status {
    if (!keep_going()) return Status(ErrorCode::kCancelled, "checking cancelled");
    auto face = load_face(manifest, i / kFaceCount, kAllFaces[i % kFaceCount]);
    checks[i].status = face.status();
    if (face.ok()) {
      checks[i].pixels = face->depth.size();
      for (float z : face->depth) checks[i].background += std::isinf(z) ? 1 : 0;
    }
    std::lock_guard<std::mutex> lock(progress_mutex);
    bar.update(++done, total);
    return Status::Ok();
  }));
  bar.finish();
  CheckResult result;
  for (const FaceCheck& check : checks) {
    if (!check.status.ok()) {
      result.problems.push_back(check.status.to_string());
      continue;
    }
    ++result.faces;
    result.pixels += check.pixels;
    result.background_pixels += check.background;
  }
  return result;
}

const char* depth_mode_name(DepthMode mode) { return mode == DepthMode::kRadial ? "radial" : "eye_z"; }

json check_json(const CheckOptions& options, const DatabaseManifest& m, const CheckResult& r) {
  return {{"command", "check"},
          {"input", options.db_dir.string()},
          {"ok", r.problems.empty()},
          {"cells", m.cells.size()},
          {"faces", m.cells.size() * kFaceCount},
          {"grid", {{"dims", m.grid.dims}, {"origin", m.grid.origin}, {"spacing", m.grid.spacing}}},
          {"face_size", {m.face_width, m.face_height}},
          {"depth", depth_mode_name(m.depth_mode)},
          {"background_fraction", r.pixels ? static_cast<double>(r.background_pixels) / r.pixels : 0.0},
          {"problems", r.problems}};
}

void print_check(const CheckOptions& options, const DatabaseManifest& m, const CheckResult& r) {
  const int64_t grid_cells = int64_t{m.grid.dims[0]} * m.grid.dims[1] * m.grid.dims[2];
  std::printf("%s: %s\n", options.db_dir.string().c_str(),
              r.problems.empty() ? "ok, the encoder accepts it" : "the encoder would refuse it");
  std::printf("  grid      %d x %d x %d, %zu cells listed (%lld holes)\n", m.grid.dims[0], m.grid.dims[1],
              m.grid.dims[2], m.cells.size(), static_cast<long long>(grid_cells - m.cells.size()));
  std::printf("  faces     %llu of %zu load, %d x %d pixels, depth %s, %.1f%% background\n",
              static_cast<unsigned long long>(r.faces), m.cells.size() * kFaceCount, m.face_width, m.face_height,
              depth_mode_name(m.depth_mode), r.pixels ? 100.0 * r.background_pixels / r.pixels : 0.0);
}

}  // namespace

int check_command(const CheckOptions& options) {
  auto manifest = load_manifest(options.db_dir, ManifestOptions{options.allow_outside_paths});
  if (!manifest.ok()) return report_error(manifest.status());
  if (options.verbosity.verbose) {
    std::fprintf(stderr, "svc: manifest ok; loading %zu faces on %d threads\n", manifest->cells.size() * kFaceCount,
                 resolve_thread_count(options.threads));
  }
  auto result = check_faces(*manifest, options);
  if (!result.ok()) return report_error(result.status());
  for (const std::string& problem : result->problems) std::fprintf(stderr, "svc: %s\n", problem.c_str());
  if (options.verbosity.json) {
    print_json(check_json(options, *manifest, *result));
  } else if (options.verbosity.show_summary()) {
    print_check(options, *manifest, *result);
  }
  return result->problems.empty() ? command_line::kExitOk : command_line::kExitFailure;
}

}  // namespace svc::cli
