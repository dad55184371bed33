// SPDX-License-Identifier: BSD-2-Clause
// What the references see of the B-cubes, and what that costs, on one database:
//
//   build/bin/svc-bench-placement DB_DIR [--qualities 55,65,75] [--threads N] [--work DIR]
//
// For each layout (the regular lattice with the nearest references; the lattice with
// the references that see most; the visibility layout) it prints the I-cubes, the share
// of B-cube samples their references see (spatial/visibility.h) and the placement time.
// Then it encodes the regular layout at each quality and fits the bytes of each B-cube,
// in units of the mean I-cube's, against the share its references see: bytes = seen +
// (unseen - seen) * (1 - share), least squares. `seen` and `unseen` are the
// LayoutCosts of spatial/placement.h.
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "common/parallel.h"
#include "database/database.h"
#include "encoder/cell_visibility.h"
#include "spatial/placement.h"
#include "spatial/visibility.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace {

using namespace svc;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Share of cell c's samples its references see together.
double seen_share(const VisibilityTable& table, uint32_t c, const std::vector<uint32_t>& refs) {
  if (refs.empty() || table.samples(c) == 0) return 0;
  const size_t seen = table.seen_by_either(c, refs[0], refs.back());
  return static_cast<double>(seen) / static_cast<double>(table.samples(c));
}

struct LayoutRow {
  const char* name;
  PlacementSettings settings;
};

int run(const std::filesystem::path& db, const std::vector<int>& qualities, int threads,
        const std::filesystem::path& work) {
  auto manifest = load_manifest(db);
  if (!manifest.ok()) {
    std::fprintf(stderr, "%s\n", manifest.status().to_string().c_str());
    return 1;
  }
  std::vector<CellIndex> cells;
  std::vector<std::optional<size_t>> sources;
  for (size_t c = 0; c < manifest->cells.size(); ++c) {
    cells.push_back(manifest->cells[c].index);
    sources.emplace_back(c);
  }
  std::array<double, 3> spacing = manifest->grid.spacing;
  for (double& s : spacing) s = s > 0 ? s : 1.0;
  const PlacementSettings regular;
  auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  auto table = measure_visibility(*manifest, sources, *reach_pairs(cells, regular.i_spacing), threads);
  if (!table.ok()) {
    std::fprintf(stderr, "%s\n", table.status().to_string().c_str());
    return 1;
  }
  // Processor time of all threads: what the table costs on a machine shared with others.
  const double cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  std::printf("%s: %zu cells, visibility table %.2f s (%.2f s processor time, %d threads)\n", db.string().c_str(),
              cells.size(), seconds_since(t0), cpu_seconds, threads);
  PlacementSettings sight = regular, layout = regular;
  sight.visibility_references = layout.visibility_references = true;
  layout.layout = Layout::kVisibility;
  std::printf("| layout | I-cubes | B-cubes | B samples seen | placement s |\n|---|---:|---:|---:|---:|\n");
  for (const LayoutRow& row :
       {LayoutRow{"regular, nearest references", regular}, LayoutRow{"regular, references by visibility", sight},
        LayoutRow{"visibility", layout}}) {
    t0 = std::chrono::steady_clock::now();
    auto placement = place_cubes(cells, manifest->grid.dims, row.settings, spacing, &*table);
    const double seconds = seconds_since(t0);
    size_t intra = 0, predicted = 0;
    double seen = 0;
    for (uint32_t c = 0; c < cells.size(); ++c) {
      if ((*placement)[c].intra) {
        ++intra;
        continue;
      }
      ++predicted;
      seen += seen_share(*table, c, (*placement)[c].references);
    }
    std::printf("| %s | %zu | %zu | %.1f %% | %.3f |\n", row.name, intra, predicted,
                predicted ? 100.0 * seen / predicted : 0.0, seconds);
  }

  std::filesystem::create_directories(work);
  auto placement = place_cubes(cells, manifest->grid.dims, regular, spacing, &*table);
  std::printf(
      "\n| quality | I-cube bytes (mean) | B-cube bytes (mean) | fit seen | fit unseen |\n"
      "|---:|---:|---:|---:|---:|\n");
  for (int quality : qualities) {
    EncoderSettings settings;
    settings.quality = quality;
    settings.threads = threads;
    settings.layout = CubeLayout::kRegular;
    settings.tools.visibility_references = false;
    const std::filesystem::path file = work / ("regular-q" + std::to_string(quality) + ".svc");
    auto summary = encode_database(db, file, settings);
    auto reader = summary.ok() ? Reader::open(file) : Result<std::unique_ptr<Reader>>(summary.status());
    if (!reader.ok()) {
      std::fprintf(stderr, "%s\n", reader.status().to_string().c_str());
      return 1;
    }
    // Reader cells follow the manifest's (y, z, x) order, as `cells` does.
    double intra_bytes = 0;
    size_t intra = 0;
    std::vector<std::pair<double, double>> points;  // (unseen share, bytes)
    for (uint32_t c = 0; c < cells.size(); ++c) {
      double bytes = 0;
      for (const FaceEntry& face : (*reader)->cells()[c].faces) bytes += static_cast<double>(face.coded_bytes);
      if ((*placement)[c].intra) {
        intra_bytes += bytes;
        ++intra;
      } else {
        points.emplace_back(1.0 - seen_share(*table, c, (*placement)[c].references), bytes);
      }
    }
    const double mean_intra = intra_bytes / static_cast<double>(intra);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (auto [x, bytes] : points) {
      const double y = bytes / mean_intra;
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
    }
    const double n = static_cast<double>(points.size());
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    const double intercept = (sy - slope * sx) / n;
    std::printf("| %d | %.0f | %.0f | %.3f | %.3f |\n", quality, mean_intra, sy * mean_intra / n, intercept,
                intercept + slope);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  svc::configure_image_loading();
  CLI::App app{"svc-bench-placement: what references see of B-cubes, and what it costs"};
  std::filesystem::path db, work = std::filesystem::temp_directory_path() / "svc-bench-placement";
  std::string qualities_text = "55,65,75";
  int threads = 0;
  app.add_option("DB_DIR", db, "svc-input database")->required();
  app.add_option("--qualities", qualities_text, "Qualities to fit the costs at")->capture_default_str();
  app.add_option("--threads", threads, "Worker threads (0: all cores)")->capture_default_str();
  app.add_option("--work", work, "Folder for the encoded files")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::vector<int> qualities;
  std::stringstream stream(qualities_text);
  for (std::string item; std::getline(stream, item, ',');) qualities.push_back(std::stoi(item));
  return run(db, qualities, resolve_thread_count(threads), work);
}
