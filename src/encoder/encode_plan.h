// SPDX-License-Identifier: BSD-2-Clause
// What a full encode and a shard encode share: the settings checked, the database read,
// the index planned (every frame's type and references from the placement rules) and
// the coding of any subset of its frames.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "codec/encoder/syntax_account.h"
#include "common/file_io.h"
#include "container/container.h"
#include "database/database.h"
#include "svc/encoder.h"
#include "svc/status.h"

namespace svc {

struct EncodePlan {
  DatabaseManifest manifest;
  // Grid, cells, coding record, and every frame's cell, face, type and references; chunk
  // offsets and statistics are filled in by coding. No cameras: they are read from the
  // manifest when needed (cell_cameras), so that an encode does not hold 176 bytes of
  // camera a face.
  ContainerIndex index;
  // How the B-faces coded so far were predicted.
  PredictionSummary prediction;
  // The B-faces' quantizer index (CodingJob::b_qindex; -1 before any B-face is coded).
  int b_qindex = -1;
  // Bits of the faces coded so far by syntax element: I-faces [0], B-faces [1].
  std::array<codec::SyntaxBits, 2> syntax;
};

// Checks `settings`, reads the manifest of `db_dir` and plans every frame.
Result<EncodePlan> plan_encode(const std::filesystem::path& db_dir, const EncoderSettings& settings);

// The face cameras of manifest.cells[cell], read again from the manifest. Errors: those
// of read_cell.
Result<CellCameras> cell_cameras(const DatabaseManifest& manifest, size_t cell);

// Where coded faces go: FACE chunks appended to a file being written.
struct FaceSink {
  std::function<Result<uint64_t>(std::span<const uint8_t> payload)> append;
  std::function<Result<std::unique_ptr<ReadOnlyFile>>()> open_written;
};

// Codes `frames` of the plan (I-faces first, then B-faces, each in frame order) into
// `sink`, filling in their index records and the plan's statistics.
Status code_planned_frames(EncodePlan& plan, std::vector<uint32_t> frames, const FaceSink& sink,
                           const EncoderSettings& settings, const EncodeProgress& progress);

// The summary of an encode of the plan's database whose coded faces are `frames`.
EncodeSummary summarize_encode(const EncodePlan& plan, uint64_t frames);

}  // namespace svc
