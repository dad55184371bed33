// SPDX-License-Identifier: BSD-2-Clause
// Encoding of a B-face (codec/common/bframe.h). Motion is not searched from scratch
// here: the caller supplies candidate vectors per macroblock and reference (from depth
// reprojection, or from log_search.h) and, optionally, node fields (from depth); the
// encoder picks vectors by SAD, screens the options by SAD and chooses the macroblock
// mode by rate-distortion cost (docs/encoder.md).
//
// Threading: every function is reentrant (no shared state); encode different faces on
// different threads. Errors: the encoder returns an empty vector for unusable arguments
// (which no decoder accepts).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/syntax_account.h"
#include "svc/types.h"

namespace svc::codec {

// `intra_qindex`: 42 indices coarser (a step 2^(42/32) = 2.48 times larger), clamped to
// the valid range. References of good quality help every face predicted from them, so
// B-faces can afford a coarser step. The default, and the offset of the trial B-faces
// that adapted_b_qindex reads (docs/encoder.md 5).
inline constexpr int kBQIndexOffset = 42;
int suggested_b_qindex(int intra_qindex);

// `intra_qindex` plus `offset`, clamped to the valid range: every B-face index above.
int b_qindex_for_offset(int intra_qindex, int offset);

// The B-faces' qindex for a database whose trial B-faces, coded at
// suggested_b_qindex(intra_qindex), coded `intra_share` (0..1) of their macroblocks
// intra: the less of the B-faces the references predict, the less a finer I-face step
// buys, so the offset shrinks from kBQIndexOffset towards kMinBQIndexOffset as the share
// grows (docs/encoder.md 5; the figures in docs/bench.md, "B-face quantizer offset").
// The frame header stores the index used.
inline constexpr int kMinBQIndexOffset = 26;
int adapted_b_qindex(int intra_qindex, double intra_share);

// BFrameParams::skip_exit_bits with the early-skip tool (chosen on the tune scenes;
// docs/bench.md, "Early skip").
inline constexpr double kEarlySkipBits = 20;

struct BFrameParams {
  // qindex of the whole B-face (residual and intra macroblocks), 0..255.
  int qindex = 138;
  // Tries the 8 half-pel neighbours of each reference's best candidate, then the 8
  // quarter-pel neighbours of the best of those (16 SADs per macroblock and reference).
  // Depth-derived candidates are already at quarter-pel precision, but the best one for
  // a whole macroblock often lies between them (docs/encoder.md 5).
  bool sub_pel_refinement = true;
  // Quarter-pel vectors; off, the encoder picks only half-pel positions (candidates
  // rounded away from zero, no quarter-pel refinement), for ablation.
  bool quarter_pel = true;
  // Rate-distortion trade-off: lambda = lambda_factor * scale^2 squared-error units, with
  // scale = quantizer_scale_q8(qindex) / 256 (the MPEG-2 quantizer_scale it replaces),
  // per bit for mode decisions (sqrt of it per bit for SAD-based vector choice), chosen
  // by the whole database's bytes against its PSNR-Y (docs/bench.md, "Figures behind code
  // constants").
  double lambda_factor = 0.08;
  // Encoder choice: levels by rate-distortion optimized quantization (codec/rdoq.h).
  bool rdoq = true;
  // Offers warped prediction (warp_prediction.h) for references whose node field is
  // given to encode_b_frame.
  bool warp = true;
  // Candidates tried per macroblock and reference: the first max_candidates of each
  // supplied list (lists come ranked, most pixels first), plus the predictor. Quarter-pel
  // depth lists hold more distinct vectors than half-pel ones did (docs/bench.md,
  // "Figures behind code constants").
  int max_candidates = 32;
  // Offers the deblocking filter (loop_filter.h); the encoder switches it on for the frame
  // where it lowers the squared error against the source.
  bool deblocking = true;
  // Offers CDEF (cdef.h), chosen by squared error plus bits (lambda as above).
  bool cdef = true;
  // Encoder choice: CDEF presets from all 14 candidate strengths; off, from every other
  // one (choose_cdef's every_candidate).
  bool full_cdef_search = true;
  // Encoder choice: every inter luma 8x8 residual block also tried as four 4x4 blocks;
  // off, only where its 8x8 transform keeps a level (inter_transform_sizes on).
  bool full_inter_split_search = true;
  // Encoder choice: a macroblock whose skip costs less than this many bits' worth of
  // squared error and side bits (lambda as above) per 256 visible luma samples is coded
  // skipped without searching motion, inter, intra or partitions; 0 searches every
  // macroblock (docs/encoder.md 5).
  double skip_exit_bits = 0;
  // Inter options (forward, backward, bidirectional, each translational or warped) are
  // screened by luma SAD plus side bits; this many of the best get the full
  // rate-distortion evaluation beside skip and intra.
  int inter_evaluations = 2;
  // Intra macroblocks are tried (off in the pass that only screens the filter banks).
  bool intra_macroblocks = true;
  // With switchable_filter: the regular bank's frame coded in full and, where another
  // bank screens clearly better, coded again with it, the cheaper kept. Off: the banks
  // are screened on a screening pass and the frame coded once.
  bool full_filter_search = true;
  // Offers the smooth and bilinear interpolation filter banks besides the regular one:
  // the frame is coded with the regular bank, and again with the bank whose predictions
  // of the same motion come clearly closer to the source, keeping the one of least
  // SSD + lambda * bits; off, the regular bank only. The sharp regular filter loses to
  // smoother ones on noisy references seen at other scales (docs/encoder.md 5).
  bool switchable_filter = true;
  // Lets each coded inter macroblock code its luma residual as one 16x16 transform block,
  // and each coded luma 8x8 block as four 4x4 ones, where that lowers the
  // rate-distortion cost (header flag kInterTransformSizesFlag); off, every residual
  // block is 8x8.
  bool inter_transform_sizes = true;
  // Splits inter macroblocks into 16x8, 8x16 or 8x8 partitions, each with its own
  // direction and vectors, where that lowers the rate-distortion cost; off, every inter
  // macroblock is one 16x16 partition (for ablation).
  bool partitions = true;
  // Codes vector differences along and across each reference's epipolar lines where the
  // hints give them (docs/codec.md 3.8); off, in x and y, for ablation.
  bool epipolar_lines = true;
  // Each coded vector and skip takes the cheapest of its vector predictors (docs/codec.md
  // 3.8); off, the first (the median) always, for ablation.
  bool vector_predictors = true;
  // Intra macroblocks are coded as in intra frames (docs/codec.md 3.7), searched with
  // the intra frame's tools: every prediction mode (off: planar and DC only, for
  // ablation), the rate-distortion mode search and the 16x16 / 8x8 / 4x4 transform
  // sizes (off: four 8x8 blocks).
  bool intra_prediction = true;
  bool intra_rd_search = true;
  bool intra_transform_sizes = true;
  // Intra 8x8 luma blocks may be split into 4x4, 8x4 or 4x8 blocks (with
  // intra_transform_sizes); off, the encoder never tries it.
  bool intra_small_blocks = true;
  // Intra macroblocks: the partitions searched in full (CodingParams::rectangular_trials
  // and small_trials).
  int intra_rectangular_trials = kRectangularPartitions;
  int intra_small_trials = kSmallPartitions;
  // With RDOQ: an intra winner's search with RDOQ keeps the partition it won with
  // (its blocks' modes, types and levels searched again); off, searches every partition.
  bool keep_intra_partition = false;
  // Chroma blocks may use CfL (codec/cfl.h; the CfL flags are still coded).
  bool intra_cfl = true;
  // Intra blocks with levels code their transform type (docs/codec.md 3.5; header byte 3
  // bit 3); off, every intra block is DCT_DCT and no type is coded.
  bool intra_transform_types = true;
};

struct BFrameStats {
  int macroblocks = 0;
  int mb_intra = 0;
  int mb_forward = 0;
  int mb_backward = 0;
  int mb_bidirectional = 0;
  int mb_skipped = 0;
  // Inter and skipped macroblocks among the above predicted by warping.
  int mb_warp = 0;
  // Inter macroblocks split into partitions (16x8, 8x16 or 8x8).
  int mb_partitioned = 0;
  // Inter macroblocks whose luma residual is one 16x16 transform block.
  int mb_luma_16x16 = 0;
  // Coded luma 8x8 blocks of inter macroblocks split into four 4x4 transform blocks.
  int luma_blocks_4x4 = 0;
  // Inter and skipped macroblocks whose luma prediction reads reference samples outside
  // the face (the cube-map border when the references are padded).
  int mb_leaving_face = 0;
  // Warp nodes transmitted, over both references.
  int64_t warp_nodes_coded = 0;
  // Distinct in-range candidate vectors tried for whole macroblocks (at most
  // max_candidates per list), summed over macroblocks and references; partitions'
  // searches are not counted.
  int64_t candidates_evaluated = 0;
  // Every luma SAD computed for vector choice (candidates, predictors, refinement).
  int64_t sad_evaluations = 0;
  // Luma squared error against the source of the whole-macroblock inter prediction of
  // the lowest SAD the screening found (forward, backward or both, warped or not), and the
  // luma pixels it covers: [0] over macroblocks coded intra, [1] over the others (the
  // skip's prediction where a cheap skip ended the search). How well the references see
  // the face, whatever was coded.
  std::array<int64_t, 2> screened_prediction_sse{};
  std::array<int64_t, 2> screened_prediction_pixels{};
  // Per macroblock, row-major (the encoder's choice; the decoder returns the same map).
  std::vector<MacroblockMode> modes;
  // The payload's bits by syntax element (syntax_account.h; the header bytes count as
  // header), estimated from the contexts' probabilities as coded.
  SyntaxBits syntax;
};

class SearchPlanes;

// Encoder only: the motion search's planes of a reference face, as encode_b_frame builds
// them when ReferenceHints::search is null. B-faces that share a reference can share
// them (built once instead of per face: same output). Thread-safe to read.
std::shared_ptr<const SearchPlanes> b_frame_search_planes(const ImageYCbCr420& reference);

// What the caller knows about the motion towards one reference; every pointer may be null
// and is read only during the call.
struct ReferenceHints {
  // One candidate list per macroblock (ceil(w/16) x ceil(h/16), row-major).
  const FaceCandidates* macroblocks = nullptr;
  // One list per 8x8 luma block (2 ceil(w/16) x 2 ceil(h/16), row-major), the candidates
  // of the partitions; ignored when of another size. Without them partitions search the
  // macroblock's list.
  const FaceCandidates* blocks = nullptr;
  // The warp node field, as in the overload above.
  const WarpField* warp = nullptr;
  // The epipolar lines of the reference's camera seen from the current one (same
  // orientation); absent, vectors are coded in x and y (docs/codec.md 3.8).
  EpipolarLines lines;
  // The reference's search planes from b_frame_search_planes; null, or built from a
  // face of another size: encode_b_frame builds them.
  const SearchPlanes* search = nullptr;
};

// Encodes `source` as a B-frame predicted from ref0 and, when not null, ref1 (decoded
// references: pass what the decoder will have), with what `hints` says of the motion
// towards each (reference 1's ignored when ref1 is null). All images must have the same
// size and consistent plane sizes, except that both references may instead be padded faces
// (cube_padding.h: the face plus the same border of 16, 32, ... 64 samples on each side),
// whose border the header then records and whose border samples vectors may reach.
// Missing or empty candidate lists fall back to the zero vector and the neighbours'
// vector; out-of-range vectors are clamped (max_vector_component). A warp node field of
// the wrong size (ceil(w/16) + 1) x (ceil(h/16) + 1), or none: no warped prediction from
// that reference; node components are clamped to max_warp_node_component, and only the
// nodes some warped macroblock uses are transmitted. `reconstruction` (optional) receives
// exactly what decode_b_frame produces; `stats` (optional) the macroblock decisions.
// Deterministic. Returns an empty vector when an image is missing, empty or inconsistent.
std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const std::array<ReferenceHints, 2>& hints,
                                    const BFrameParams& params, ImageYCbCr420* reconstruction, BFrameStats* stats);

// The header bytes of `header` (this build's syntax version), which must hold values
// parse_b_frame_header accepts.
std::array<uint8_t, kBFrameHeaderBytes> serialize_b_frame_header(const BFrameHeader& header);

}  // namespace svc::codec
