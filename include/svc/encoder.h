// Encoding an svc-input database (docs/input-format.md) into an .svc file.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>

#include "svc/status.h"

namespace svc {

enum class MotionSearch : uint8_t {
  kDepth = 0,        // candidates from depth and camera reprojection (default)
  kLogarithmic = 1,  // image-space logarithmic search in a 64-pixel window
};

struct EncoderSettings {
  // 1 (smallest) .. 100 (best). Maps to a quantiser scale, see docs/codec.md.
  int quality = 75;
  // When non-zero, overrides quality: the codec quantiser scale, 1..112.
  int quant_scale = 0;
  // Worker threads; 0 uses the machine's hardware concurrency. Output bytes do not
  // depend on this.
  int threads = 0;
  // I-cube spacing per axis (x, y, z): {3,1,3} is one I-cube per 3x3 group of a layer.
  std::array<int32_t, 3> i_spacing{3, 1, 3};
  // Every cell an I-cube (same as i_spacing {1,1,1}).
  bool intra_only = false;
  MotionSearch motion = MotionSearch::kDepth;
};

// Fills settings with the defaults documented on each field.
EncoderSettings default_encoder_settings();

// Statistics of one frame type (I or B) over a whole encode.
struct FrameTypeStats {
  uint64_t faces = 0;
  uint64_t bytes = 0;
  uint64_t mb_intra = 0;
  uint64_t mb_forward = 0;
  uint64_t mb_backward = 0;
  uint64_t mb_bidirectional = 0;
  uint64_t mb_skipped = 0;       // predicted with no residual
  uint64_t candidate_vectors = 0;  // unique candidates summed over predicted faces' macroblocks
  uint64_t candidate_macroblocks = 0;
};

struct EncodeSummary {
  uint64_t cells = 0;
  uint64_t faces = 0;
  uint64_t raw_bytes = 0;   // 3 bytes a pixel of RGB
  uint64_t file_bytes = 0;  // size of the .svc file
  int quant_scale = 0;
  double seconds = 0;
  FrameTypeStats intra;
  FrameTypeStats predicted;
};

// Called from the encoding thread after each face: (faces done, faces total). Return
// false to cancel; the encode then fails with kCancelled and writes nothing.
using EncodeProgress = std::function<bool(uint64_t done, uint64_t total)>;

// Reads the database in `db_dir` and writes `out_path`. The output appears only when
// complete: on any error (bad input, unwritable path, cancel) nothing is left at
// `out_path` and an existing file there is untouched. Errors name the cell, face and
// file at fault. Thread-safe: independent calls may run concurrently.
Result<EncodeSummary> encode_database(const std::filesystem::path& db_dir,
                                      const std::filesystem::path& out_path,
                                      const EncoderSettings& settings,
                                      const EncodeProgress& progress = {});

// Quantiser scale used for a quality (1..100). Monotonic: higher quality, finer scale.
int quant_scale_for_quality(int quality);

}  // namespace svc
