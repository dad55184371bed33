// SPDX-License-Identifier: BSD-2-Clause
// svc check: validates a database as the encoder reads it (manifest, every image's size,
// channels and depth) without encoding, reports every problem, and summarises it. A
// cell may list some of its faces (what svc decode --face writes): valid, and said to be
// beyond the encoder, which codes whole cubes.
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
  uint64_t listed = 0;                // faces the manifest lists
  uint64_t partial_cells = 0;         // cells that list fewer than six faces
  uint64_t faces = 0;                 // faces that load
  uint64_t pixels = 0;                // in the faces that load
  uint64_t background_pixels = 0;     // of those, pixels whose depth saw no geometry
};

struct FaceCheck {
  Status status;
  uint64_t pixels = 0;
  uint64_t background = 0;
};

Result<CheckResult> check_faces(const DatabaseManifest& manifest, const std::vector<FaceFileProblem>& file_problems,
                                const CheckOptions& options) {
  const size_t total = manifest.cells.size() * kFaceCount;
  std::vector<FaceCheck> checks(total);
  std::vector<bool> listed(total), file_checked(total, true);
  for (size_t i = 0; i < total; ++i)
    listed[i] = lists_face(manifest.cells[i / kFaceCount].listed_faces, kAllFaces[i % kFaceCount]);
  for (const FaceFileProblem& problem : file_problems) {
    const size_t i = *find_cell(manifest, problem.cell) * kFaceCount + static_cast<size_t>(problem.face);
    checks[i].status = problem.status;
    file_checked[i] = false;
  }
  std::mutex progress_mutex;
  uint64_t done = 0;
  ProgressBar bar("checking", options.verbosity.show_progress());
  SVC_RETURN_IF_ERROR(parallel_for(total, resolve_thread_count(options.threads), [&](size_t i) -> Status {
    if (!keep_going()) return Status(ErrorCode::kCancelled, "checking cancelled");
    if (listed[i] && file_checked[i]) {
      auto face = load_face(manifest, i / kFaceCount, kAllFaces[i % kFaceCount]);
      checks[i].status = face.status();
      if (face.ok()) {
        checks[i].pixels = face->depth.size();
        for (float z : face->depth) checks[i].background += std::isinf(z) ? 1 : 0;
      }
    }
    std::lock_guard<std::mutex> lock(progress_mutex);
    bar.update(++done, total);
    return Status::Ok();
  }));
  bar.finish();
  CheckResult result;
  for (const ManifestCell& cell : manifest.cells) result.partial_cells += cell.listed_faces != kAllFacesListed;
  for (size_t i = 0; i < total; ++i) {
    if (!listed[i]) continue;
    ++result.listed;
    const FaceCheck& check = checks[i];
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
          {"encodable", r.problems.empty() && r.partial_cells == 0},
          {"cells", m.cells.size()},
          {"partial_cells", r.partial_cells},
          {"faces", r.listed},
          {"grid", {{"dims", m.grid.dims}, {"origin", m.grid.origin}, {"spacing", m.grid.spacing}}},
          {"face_size", {m.face_width, m.face_height}},
          {"depth", depth_mode_name(m.depth_mode)},
          {"background_fraction", r.pixels ? static_cast<double>(r.background_pixels) / r.pixels : 0.0},
          {"problems", r.problems}};
}

void print_check(const CheckOptions& options, const DatabaseManifest& m, const CheckResult& r) {
  const int64_t grid_cells = int64_t{m.grid.dims[0]} * m.grid.dims[1] * m.grid.dims[2];
  const char* verdict = !r.problems.empty() ? "the encoder would refuse it"
                        : r.partial_cells != 0
                            ? "ok, a database of some faces of its cells (svc encode needs all six faces of a cell)"
                            : "ok, the encoder accepts it";
  std::printf("%s: %s\n", options.db_dir.string().c_str(), verdict);
  std::printf("  grid      %d x %d x %d, %zu cells listed (%lld holes)\n", m.grid.dims[0], m.grid.dims[1],
              m.grid.dims[2], m.cells.size(), static_cast<long long>(grid_cells - m.cells.size()));
  if (r.partial_cells != 0) {
    std::printf("  partial   %llu cells list fewer than six faces\n",
                static_cast<unsigned long long>(r.partial_cells));
  }
  std::printf("  faces     %llu of %llu listed load, %d x %d pixels, depth %s, %.1f%% background\n",
              static_cast<unsigned long long>(r.faces), static_cast<unsigned long long>(r.listed), m.face_width,
              m.face_height, depth_mode_name(m.depth_mode),
              r.pixels ? 100.0 * r.background_pixels / r.pixels : 0.0);
}

}  // namespace

int check_command(const CheckOptions& options) {
  // Every face's files are checked and reported, not the first bad one alone.
  std::vector<FaceFileProblem> file_problems;
  ManifestOptions manifest_options;
  manifest_options.allow_outside_paths = options.allow_outside_paths;
  manifest_options.allow_partial_cells = true;
  manifest_options.file_problems = &file_problems;
  auto manifest = load_manifest(options.db_dir, manifest_options);
  if (!manifest.ok()) return report_error(manifest.status());
  if (options.verbosity.verbose) {
    std::fprintf(stderr, "svc: manifest read; loading its faces on %d threads\n",
                 resolve_thread_count(options.threads));
  }
  auto result = check_faces(*manifest, file_problems, options);
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
