// SPDX-License-Identifier: BSD-2-Clause
// How close an .svc file's decoded faces are to the database they were encoded from:
// what `svc encode --psnr` and `svc demo` report.
#pragma once

#include <filesystem>
#include <vector>

#include "command_line/progress.h"
#include "database/database.h"
#include "svc/metrics.h"
#include "svc/reader.h"

namespace svc::cli {

struct QualityReport {
  SquaredError luma;
  SquaredError rgb;
  double ssim_sum = 0;  // luma SSIM summed over the faces
  uint64_t faces = 0;
  double psnr_y() const { return luma.psnr(); }
  double psnr_rgb() const { return rgb.psnr(); }
  double ssim() const { return faces ? ssim_sum / faces : 0.0; }
  void add(const QualityReport& other);
};

// Compares the six decoded faces of manifest.cells[ordinal] with their source images.
Result<QualityReport> measure_cell(Reader& reader, const DatabaseManifest& manifest, size_t ordinal);

// Compares every cell of the manifest, on `threads` threads; the figures do not depend
// on the thread count. Stops with kCancelled on SIGINT or SIGTERM.
Result<QualityReport> measure_database(Reader& reader, const DatabaseManifest& manifest, int threads,
                                       command_line::ProgressBar* bar);

}  // namespace svc::cli
