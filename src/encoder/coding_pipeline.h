// SPDX-License-Identifier: BSD-2-Clause
// The coding of a list of faces into a container: shared by a full encode, a shard
// encode and `svc add`, so all three code, store and count faces the same way.
#pragma once

#include <array>
#include <cstdint>
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

// Bytes of decoded reference I-faces a coding run keeps at most; one run holds these,
// the faces in flight (4 per thread) and the index. docs/format.md, "Memory".
inline constexpr uint64_t kReferenceCacheBytes = 64ull << 20;

// The budget each of a coding run's three reference caches (decoded, padded, search planes) gets:
// kReferenceCacheBytes, or the environment's SVC_REFERENCE_CACHE_BYTES when that is a whole number of bytes from 1
// to kReferenceCacheBytes (a smaller budget makes a small database reach it, as the memory test does). The coded
// bytes do not depend on it.
uint64_t reference_cache_bytes();

struct CodingJob {
  // The index being built. Each frame to code has its cell, face, kind and references
  // set; coding fills in its chunk offset and size and adds to stats[kind].
  ContainerIndex* index = nullptr;
  // Frames to code, in cell order. I-faces are coded first (B-faces predict from their
  // reconstructions), then B-faces; each group keeps this order.
  std::vector<uint32_t> frames;
  // The source color and depth of a frame to code (or of a reference I-face that is in
  // no file, see below).
  std::function<Result<FaceData>(uint32_t frame)> load;
  // The camera of a frame's face, for B-faces and their references: an encode's index
  // holds no cameras (they are read from the manifest again), `svc add`'s does.
  std::function<Result<Camera>(uint32_t frame)> camera;
  // Appends a FACE chunk to the file; returns its offset.
  std::function<Result<uint64_t>(std::span<const uint8_t> payload)> append;
  // Tools the coder may use (encode's settings; all of them for `svc add`).
  CodingTools tools;
  // Opens the file being written for reading, once the I-faces are in it. A reference
  // I-face with a chunk offset is decoded from there (exactly the encoder's
  // reconstruction); one without (coded by another shard) is coded again from `load`,
  // which gives the same reconstruction. Either way only kReferenceCacheBytes of them
  // stay in memory.
  std::function<Result<std::unique_ptr<ReadOnlyFile>>()> open_written;
  int threads = 1;
  const char* action = "encode";  // names the run in the cancellation message
  EncodeProgress progress;
  // B-faces coded once, before the others, at the default B-face quantizer offset: the
  // share of their macroblocks coded intra sets every B-face's quantizer index
  // (codec::adapted_b_qindex, docs/encoder.md 5). Their sources must be loadable; the
  // same list gives the same bytes, so every part of a sharded encode takes the whole
  // database's (trial_frames). Empty: the default offset.
  std::vector<uint32_t> trial_frames;
  // 0..255: the B-faces' quantizer index is the I-faces' plus this (clamped to 255),
  // and trial_frames is ignored.
  int b_qindex_offset = -1;
  // Border of padded references in units of 16 luma samples (EncoderSettings).
  int cube_border_units = EncoderSettings{}.cube_border_units;
  // Filled by coding: the B-faces' quantizer index (-1 when no B-face was coded).
  int b_qindex = -1;
  // Filled by coding: how the B-faces' macroblocks were predicted (EncodeSummary::prediction).
  PredictionSummary prediction;
  // Filled by coding: the bits of the stored faces by syntax element, I-faces [0] and
  // B-faces [1] (EncodeSummary::intra_syntax_bytes, predicted_syntax_bytes).
  std::array<codec::SyntaxBits, 2> syntax;
};

// B-cubes whose faces are CodingJob::trial_frames.
inline constexpr size_t kTrialCubes = 3;

// The trial B-faces among `frames` of `index`, in cell order: every face of kTrialCubes
// B-cubes spread evenly over the B-cubes `frames` holds whole, ordered by the distance to
// their nearest reference cube, then by cell (all of them when fewer).
std::vector<uint32_t> trial_frames(const ContainerIndex& index, std::span<const uint32_t> frames);

// Whether B-faces of `index` are coded from padded references with `tools`: the tool is
// on and the faces are square (cube faces).
bool uses_cube_references(const ContainerIndex& index, const CodingTools& tools);

// Codes job.frames with the index's coding settings and appends them in order. Bytes do
// not depend on the thread count. Errors: loading, the file's, or kCancelled when
// progress returns false.
Status code_faces(CodingJob& job);

}  // namespace svc
