// B-frame coding of one face: each 16x16 macroblock is intra-coded, predicted from one of
// up to two reference faces (forward = reference 0, backward = reference 1) or from the
// average of both, or skipped (predicted with the neighbours' vectors, no residual).
// Motion vectors are not searched here: the caller supplies candidate vectors per
// macroblock and reference (from depth reprojection, or from log_search.h), and the
// encoder picks among them by SAD, then chooses the macroblock mode by rate-distortion
// cost. Bitstream syntax: docs/codec.md, section 10.
//
// Threading: every function is reentrant (no shared state); encode different faces on
// different threads. Errors: the encoder returns an empty vector for unusable arguments
// (which no decoder accepts); the decoder returns kInvalidArgument for a bad size or
// reference set and kCorruptData for bytes that are not a valid B-frame. It never reads
// outside its inputs, whatever the bytes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/frame_codec.h"
#include "codec/motion.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc::codec {

inline constexpr uint8_t kBFrameSyntaxVersion = 1;
// Frame type, syntax version, quant_scale, reserved zero, reference count.
inline constexpr int kBFrameHeaderBytes = 5;

// The coding of one macroblock, as the decoder reports it (svc inspect draws intra red,
// forward/backward/bidirectional green, skipped blue).
enum class MacroblockMode : uint8_t {
  kIntra = 0,
  kForward = 1,        // predicted from reference 0
  kBackward = 2,       // predicted from reference 1
  kBidirectional = 3,  // rounded mean of both predictions
  kSkipped = 4,        // predicted mode and vectors inherited, no residual
};

// The quant_scale this library suggests for B-frames next to I-frames coded at
// `intra_quant_scale`: round(1.25 x), clamped to the valid range. References of good
// quality help every face predicted from them, so B-frames can afford a coarser step
// (MPEG-2 Test Model 5 uses a ratio of 1.4). The frame header stores the scale used.
int suggested_b_quant_scale(int intra_quant_scale);

struct BFrameParams {
  // quant_scale of the whole B-frame (residual and intra macroblocks), 1..112.
  int quant_scale = 10;
  // Tries the 8 half-pel neighbours of each reference's best candidate. Depth-derived
  // candidates are already at half-pel precision; refinement buys little there
  // (measured in docs/codec.md) and costs 8 SADs per macroblock and reference.
  bool half_pel_refinement = false;
  // Rate-distortion trade-off: lambda = lambda_factor * quant_scale^2 squared-error units
  // per bit for mode decisions (sqrt of it per bit for SAD-based vector choice).
  double lambda_factor = 0.12;
};

struct BFrameStats {
  int macroblocks = 0;
  int mb_intra = 0;
  int mb_forward = 0;
  int mb_backward = 0;
  int mb_bidirectional = 0;
  int mb_skipped = 0;
  // Distinct in-range candidate vectors supplied, summed over macroblocks and
  // references (mean per macroblock and reference: divide by macroblocks * references).
  int64_t candidates_evaluated = 0;
  // Every luma SAD computed for vector choice (candidates, predictors, refinement).
  int64_t sad_evaluations = 0;
  // Per macroblock, row-major (the encoder's choice; the decoder returns the same map).
  std::vector<MacroblockMode> modes;
};

// Encodes `source` as a B-frame predicted from ref0 and, when not null, ref1 (decoded
// references: pass what the decoder will have). All images must have the same size and
// consistent plane sizes. candidates0/candidates1 hold one list per macroblock
// (ceil(w/16) x ceil(h/16), row-major); missing or empty lists fall back to the zero
// vector and the neighbours' vector; out-of-range vectors are clamped
// (max_vector_component). `reconstruction` (optional) receives exactly what
// decode_b_frame produces; `stats` (optional) the macroblock decisions. Deterministic.
// Returns an empty vector when an image is missing, empty or inconsistent.
std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const FaceCandidates& candidates0,
                                    const FaceCandidates& candidates1, const BFrameParams& params,
                                    ImageYCbCr420* reconstruction, BFrameStats* stats);

struct BFrameHeader {
  int quant_scale = 0;
  int reference_count = 0;  // 1 or 2
};

// Validates and reads the header of a B-frame payload (kCorruptData / kUnsupported).
Status parse_b_frame_header(std::span<const uint8_t> bytes, BFrameHeader* out);

// Decodes a B-frame of width x height. ref1 must be null exactly when the frame was coded
// with one reference; references must be width x height with consistent planes
// (kInvalidArgument otherwise). `modes` (optional) receives the per-macroblock modes,
// row-major. On error `out` and `modes` are left in an unspecified but valid state.
Status decode_b_frame(std::span<const uint8_t> bytes, int width, int height,
                      const ImageYCbCr420& ref0, const ImageYCbCr420* ref1, ImageYCbCr420* out,
                      std::vector<MacroblockMode>* modes = nullptr);

}  // namespace svc::codec
