// SPDX-License-Identifier: BSD-2-Clause
// Encoding an svc-input database (docs/input-format.md) into an .svc file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "svc/export.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

// The coding tools the encoder may use. Every tool is on by default; switching one off
// only restricts the encoder's choices (every decoder still reads the stream), so the
// gain of each tool can be measured on its own (`svc encode --disable-tool NAME`, the
// ablation of `svc bench --ablation`). Not stored in the file: `svc add` uses all tools.
struct CodingTools {
  // B-faces: macroblocks predicted through a field of corner vectors (docs/codec.md 5.6).
  bool warped_prediction = true;
  // B-faces: the half-pel, then quarter-pel neighbours of the best candidate vector are
  // tried as well.
  bool sub_pel_refinement = true;
  // I-faces: the 33 angular intra prediction modes; without them every block is
  // predicted by the planar or DC mode (docs/codec.md 5.2).
  bool intra_directional = true;
  // I-faces: each block's mode and whether it keeps its levels chosen by
  // rate-distortion cost among the best modes by SATD (docs/codec.md 3.2).
  bool intra_rd_search = true;
  // B-faces: quarter-pel vectors (off: the encoder keeps to half-pel positions).
  bool quarter_pel = true;
  // B-cubes: the (at most) two I-cubes in reach that together see most of the cell, from
  // depth, rather than the nearest two (docs/format.md, "I-cube placement").
  bool visibility_references = true;
  // B-faces: references padded with the adjacent faces of their cube, so vectors that
  // leave the reference face find what lies past its edge (docs/codec.md 5.7). Off: the
  // bare reference faces, and a B-face depends on its reference faces only.
  bool cube_references = true;
  // Every face: the deblocking filter (docs/codec.md 5.8), on where it lowers the error.
  bool deblocking = true;
  // Every face: CDEF deringing after deblocking (docs/codec.md 5.8.2), per 64x64 unit
  // where it pays.
  bool cdef = true;
  // B-faces: each face picks its interpolation filter bank (regular, smooth, bilinear) by
  // rate-distortion cost (off: the regular bank only; the encoder codes each face once).
  bool switchable_filter = true;
  // I- and B-faces: each block's levels chosen by rate-distortion optimized quantization
  // (weighing each level, one less and zero, and where the block ends) rather than by
  // rounding with a dead zone. Encoder only.
  bool rdoq = true;
  // B-faces: inter macroblocks split into 16x8, 8x16 or 8x8 partitions, each with its own
  // direction and vectors from its own pixels' depth (docs/codec.md 3.7). Off: 16x16 only.
  bool partitions = true;
  // I-faces: each 16x16 luma region coded as one 16x16 transform block, four 8x8 or 8x8
  // blocks split into four 4x4, by rate-distortion cost (docs/codec.md 3.1). Off: 8x8 only.
  bool transform_sizes = true;
  // B-faces: each coded inter macroblock's luma residual coded as one 16x16 transform
  // block or four 8x8 blocks, each of those whole or as four 4x4 blocks, by
  // rate-distortion cost (docs/codec.md 3.7). Off: 8x8 only.
  bool inter_transform_sizes = true;
  // I-faces and B-face intra macroblocks: chroma blocks may be predicted from the
  // co-located reconstructed luma (CfL, docs/codec.md 3.3 and 3.7), by rate-distortion
  // cost against the regular modes. Off: never.
  bool cfl = true;
  // I-faces and B-face intra macroblocks: each block with levels uses the DCT or an
  // integer DST-VII per direction (docs/codec.md 5.5.2), by rate-distortion cost, and
  // codes its choice. Off: DCT only, no type coded (a header flag says so).
  bool transform_types = true;
  // I-faces: residuals quantized with a frequency-weighted matrix (coarser high
  // frequencies, docs/codec.md 5.4) instead of one flat step per transform size. Off by
  // default, since flat measures better in PSNR; `svc encode --quant-matrix weighted`.
  // Not one of the --disable-tool names.
  bool weighted_quant_matrix = false;
  // B-faces: intra macroblocks predicted in every mode of the intra frame's prediction
  // (docs/codec.md 3.7). Off: planar and DC only. (Their transform sizes, mode search
  // and directional modes also follow transform-sizes, intra-rd-search and
  // intra-directional.)
  bool b_intra_prediction = true;
  // B-faces: each coded vector, and each skip, takes the vector predictor (the median,
  // the left, top or top-right macroblock's vector) it codes cheapest from
  // (docs/codec.md 3.8). Off: the median always.
  bool vector_predictors = true;
  // B-faces: vector and warp node differences coded along and across the epipolar line
  // of each reference (from the cameras; docs/codec.md 3.8), predictors and candidates
  // taken onto the line. Off: in x and y.
  bool epipolar_lines = true;
  // I-faces: every block ranks all 35 prediction modes by SATD. Off: planar, DC, the most
  // probable modes and every fourth angular mode, then the two on each side of the best
  // of those (at most 18 modes), as B-face intra macroblocks always rank them
  // (docs/encoder.md 4). Encoder only.
  bool full_intra_mode_search = true;
  // B-faces: an intra macroblock's 8x8 luma blocks are also tried as four 4x4, two 8x4
  // or two 4x8 blocks. Off: its blocks are 16x16, 16x8, 8x16, 16x4, 4x16 or 8x8 only
  // (docs/encoder.md 4). Encoder only.
  bool b_intra_small_blocks = true;
  // Every face: CDEF presets chosen among 14 candidate strengths. Off: among every other
  // one of them, in half the search time (docs/encoder.md 4). Encoder only.
  bool full_cdef_search = true;
  // B-faces: every luma 8x8 residual block of an inter macroblock is also tried as four
  // 4x4 transform blocks. Off: only where its 8x8 transform keeps a level, since a block
  // that quantizes to nothing as a whole rarely pays for four (docs/encoder.md 4).
  // Encoder only.
  bool full_inter_split_search = true;
  // I-faces and B-face intra macroblocks: every 16x16 halves and strips partition and
  // every 4x4, 8x4 and 4x8 partition of a coded 8x8 block searched by rate-distortion
  // cost. Off: a first stage ranks them by an open-loop SATD estimate and only the
  // cheapest halves or strips partition and the cheapest smaller partition of each 8x8
  // block are searched (the 8x8 split and the 16x16 block always; docs/encoder.md 2.2).
  // Encoder only.
  bool full_intra_partition_search = true;
  // B-faces: an intra macroblock chosen with plain quantization is searched again with
  // RDOQ in every partition. Off: in the partition it was chosen in, its blocks' modes,
  // transform types and levels searched again (docs/encoder.md 5). Encoder only.
  bool rdoq_intra_partition_search = true;
  // B-faces, with switchable-filter: the frame is coded in full with the regular bank
  // and, where the screening of its motion through the other banks finds one clearly
  // closer, coded in full again with that bank, the cheaper kept. Off: a first pass
  // without intra macroblocks, partitions or RDOQ gives the motion the banks are
  // screened by, and the frame is coded in full once, with the bank screened best
  // (docs/encoder.md 5). Encoder only.
  bool full_filter_search = true;
  // B-faces: a macroblock whose skip costs less than 20 bits' worth of squared error and
  // side bits per 256 visible luma samples is coded skipped without searching its
  // motion, inter, intra or partition options. Off: every macroblock searched in full,
  // for ablation (docs/encoder.md 5). Encoder only.
  bool early_skip = true;

  bool operator==(const CodingTools&) const = default;
};

// Where the encoder puts I-cubes (docs/format.md, "I-cube placement").
enum class CubeLayout : uint8_t {
  // The i_spacing lattice, plus I-cubes where the references in reach see too little of
  // the cells around them and an I-cube costs less than predicting them.
  kVisibility = 0,
  // The i_spacing lattice alone: one I-cube per group.
  kRegular = 1,
};

// Names of the coding tools, in the order of CodingTools, for --disable-tool.
SVC_API std::vector<std::string> coding_tool_names();

// Names of the coding tools switched off in `tools`, in the order of coding_tool_names().
SVC_API std::vector<std::string> disabled_coding_tools(const CodingTools& tools);

// Switches the tool called `name` off. Errors: kInvalidArgument naming the valid tools
// when `name` is not one of coding_tool_names().
SVC_API Status disable_coding_tool(CodingTools* tools, std::string_view name);

// Encoder speed settings, 0 (the default: every tool) to kMaxEncoderSpeed. Each step
// switches off more of the coding tools that cost the most encode time for the bytes
// they save, and the two highest also the visibility layout's planning; docs/encoder.md 4
// lists them with their BD-rate and time. Thread-safe (fixed tables); outside
// 0..kMaxEncoderSpeed the tools list is empty and the layout kVisibility.
inline constexpr int kMaxEncoderSpeed = 5;
SVC_API std::vector<std::string> speed_disabled_tools(int speed);
SVC_API CubeLayout speed_layout(int speed);

struct EncoderSettings {
  // 1 (smallest) .. 100 (best), spread evenly over the quantizer indices
  // (qindex_for_quality): 100 -> 0 (the finest step, not lossless), 75 -> 64, 50 -> 129,
  // 1 -> 255 (the I-faces' index; B-faces use 26 to 42 more, b_qindex_offset).
  int quality = 75;
  // When 0..255, overrides quality: the codec quantizer index (docs/codec.md, section 5.4).
  // -1: use quality.
  int qindex = -1;
  // Quantizer indices the B-faces use above the I-faces' (the sum clamped to 255):
  // -1 chooses 26..42 per database from trial B-faces (docs/encoder.md 5); 0..255 fixes
  // it (to measure the choice).
  int b_qindex_offset = -1;
  // Width of the cube-map border of B-faces' padded references (cube-references), in
  // units of 16 luma samples, 1..4 (docs/codec.md 5.7). 4 lets vectors reach furthest
  // past a face's edge; a narrower border pads less per reference (docs/encoder.md 7).
  int cube_border_units = 4;
  // Worker threads; 0 uses the machine's hardware concurrency. Output bytes do not
  // depend on this.
  int threads = 0;
  // I-cube spacing per axis (x, y, z): {3,1,3} is one I-cube per 3x3 group of a layer.
  std::array<int32_t, 3> i_spacing{3, 1, 3};
  // Every cell an I-cube (same as i_spacing {1,1,1}).
  bool intra_only = false;
  // The visibility layout starts from the i_spacing lattice; kRegular keeps it alone.
  CubeLayout layout = CubeLayout::kVisibility;
  MotionSearch motion = MotionSearch::kDepth;
  CodingTools tools;
  // Store every face's depth beside its color (docs/codec.md 8), so that readers can
  // decode it (Reader::decode_face_depth). Off by default.
  bool depth = false;
  // With depth: the largest difference allowed between a decoded inverse-depth code and
  // the source's (codec/common/depth.h units: 65535 near / z), 0..255; 0 is lossless in
  // those codes. Pixels without geometry always stay exact.
  int depth_max_error = 0;
  // Let the manifest name face files outside the database folder (absolute paths,
  // "../"). Off by default: such a manifest is refused with kBadInput naming the file.
  bool allow_outside_paths = false;
};

// Fills settings with the defaults documented on each field.
SVC_API EncoderSettings default_encoder_settings();

// Applies encoder speed `speed`: switches speed_disabled_tools(speed) off in
// settings->tools (on top of any already off) and sets settings->layout to
// speed_layout(speed). Thread-safe. Errors: kInvalidArgument outside
// 0..kMaxEncoderSpeed; `settings` is unchanged then.
SVC_API Status apply_encoder_speed(EncoderSettings* settings, int speed);

// The syntax elements the encode summary counts bytes by (EncodeSummary::
// intra_syntax_bytes, predicted_syntax_bytes), in this order (docs/encoder.md, "Syntax
// accounting"):
//   header      frame header fields, and any bin no other element claims;
//   modes       skip flags, the macroblock type and prediction direction (intra,
//               forward, backward, bidirectional, warp), luma and chroma intra modes
//               with the CfL parameters;
//   partitions  inter partitions, transform size splits and transform types;
//   vectors     motion vector differences, vector predictor indices, warp nodes,
//               epipolar lines;
//   levels      the coefficient syntax: coded-block flags, end of block, significance,
//               levels, signs and their Golomb / bypass remainders;
//   filters     CDEF syntax (the loop filter flags are header bits).
inline constexpr size_t kSyntaxElementCount = 6;
// {"header", "modes", "partitions", "vectors", "levels", "filters"}. Thread-safe.
SVC_API std::vector<std::string> syntax_element_names();

// What the encoder saw of the B-faces' prediction (docs/encoder.md 12).
struct SVC_API PredictionSummary {
  // Macroblocks (inter or skipped) whose prediction reads reference samples outside the
  // reference face: from the cube border with cube references, else from the edge
  // extension.
  uint64_t mb_leaving_face = 0;
  // Inter and skipped macroblocks predicted by warping.
  uint64_t mb_warp = 0;
  // Luma squared error against the source of the lowest-SAD whole-macroblock inter
  // prediction the encoder screened for each macroblock, and the luma pixels it covers:
  // [0] over macroblocks coded intra, [1] over the others. How well the references see
  // the B-faces, whatever was coded.
  std::array<uint64_t, 2> screened_sse{};
  std::array<uint64_t, 2> screened_pixels{};

  PredictionSummary& operator+=(const PredictionSummary& other);
};

struct EncodeSummary {
  uint64_t cells = 0;
  uint64_t faces = 0;
  uint64_t raw_bytes = 0;   // 3 bytes a pixel of RGB
  uint64_t file_bytes = 0;  // size of the .svc file
  int qindex = 0;           // the I-faces' quantizer index
  // The B-faces' quantizer index, chosen per database from trial B-faces (docs/encoder.md
  // 5); -1 when this run coded no B-face.
  int b_qindex = -1;
  double seconds = 0;
  FaceTypeStats intra;
  FaceTypeStats predicted;
  // How the B-faces' macroblocks were predicted. Not stored in the file; filled as the
  // syntax bytes below are.
  PredictionSummary prediction;
  // Bytes of the I-faces' and of the B-faces' payloads by syntax element (indexed as
  // syntax_element_names()), estimated from the contexts' probabilities as coded (-log2 p
  // per bin, 1 bit per bypass bin, 8 bits per header byte): each sum is within a fraction
  // of a percent of that face type's payload bytes (intra.bytes, predicted.bytes), the
  // range coder's final bytes making the difference. Not stored in the file. Filled by
  // encode_database and encode_shard (the faces this part coded); merges and `svc add`
  // do not compute it.
  std::array<double, kSyntaxElementCount> intra_syntax_bytes{};
  std::array<double, kSyntaxElementCount> predicted_syntax_bytes{};
};

// Called from the encoding thread after each face: (faces done, faces total). Return
// false to cancel; the encode then fails with kCancelled and writes nothing.
using EncodeProgress = std::function<bool(uint64_t done, uint64_t total)>;

// Reads the database in `db_dir` and writes `out_path`. The output appears only when
// complete: on any error (bad input, unwritable path, cancel) nothing is left at
// `out_path` and an existing file there is untouched. Errors name the cell, face and
// file at fault. Memory: a bounded window of faces (64 MiB of reference I-faces, 64 MiB
// of them padded for cube references, 5 faces per thread) plus the manifest and index,
// whatever the database's size (docs/format.md, "Memory"). Thread-safe: independent
// calls may run concurrently.
SVC_API Result<EncodeSummary> encode_database(const std::filesystem::path& db_dir,
                                              const std::filesystem::path& out_path,
                                              const EncoderSettings& settings, const EncodeProgress& progress = {});

// --- Sharded encoding (docs/format.md, "Shards") ------------------------------------------

// Encodes part `shard` (1..shard_count, at most kMaxShards) of the database into the
// part file `part_path`: every shard plans the whole encode, codes its share of the
// I-faces and of the B-faces, and codes again the few reference I-faces another shard
// owns. merge_shards joins the parts into exactly the bytes encode_database writes,
// whatever the shard count. The part appears only when complete (as encode_database);
// a failed or killed shard can be run again alone. Settings must be the same for every
// part (the merge checks); every coding tool is on (a switched-off tool is refused with
// kInvalidArgument, since parts do not record tools). The summary counts this part's
// faces (file_bytes: the part).
// Thread-safe: independent calls may run concurrently.
inline constexpr int kMaxShards = 65536;
SVC_API Result<EncodeSummary> encode_shard(const std::filesystem::path& db_dir,
                                           const std::filesystem::path& part_path, const EncoderSettings& settings,
                                           int shard, int shard_count, const EncodeProgress& progress = {});

struct MergeSummary {
  uint64_t parts = 0;
  uint64_t cells = 0;
  uint64_t faces = 0;
  uint64_t file_bytes = 0;
  double seconds = 0;
};

// Joins the part files of one sharded encode (any order) into `out_path`. Refused, with
// nothing written and an error naming the part file: a file that is not a complete,
// undamaged part (every chunk's CRC is checked); parts of different databases, settings,
// shard counts or svc versions; a part given twice; a part missing. Output rules as
// encode_database. Thread-safe: independent calls may run concurrently.
SVC_API Result<MergeSummary> merge_shards(const std::vector<std::filesystem::path>& parts,
                                          const std::filesystem::path& out_path);

// --- Incremental additions (docs/format.md, "Incremental additions") ---------------------

struct AddSettings {
  // Worker threads; 0 uses the machine's hardware concurrency. Output bytes do not
  // depend on this.
  int threads = 0;
  // As EncoderSettings::allow_outside_paths.
  bool allow_outside_paths = false;
};

struct AddSummary {
  uint64_t cells_before = 0;   // cells in the file before
  uint64_t cells_added = 0;    // cells of the database that were not in the file
  uint64_t cells_present = 0;  // cells of the database already in the file (left as they were)
  uint64_t intra_cells_added = 0;
  uint64_t predicted_cells_added = 0;
  uint64_t faces_added = 0;
  uint64_t bytes_appended = 0;                // face chunks and the new index
  uint64_t file_bytes = 0;                    // size of the file after the commit
  uint64_t generation = 0;                    // commit generation now in use
  std::array<int32_t, 3> grid_dims{0, 0, 0};  // of the file after the commit
  double seconds = 0;
};

// Adds the cells of the database in `db_dir` that `svc_file` does not hold yet, without
// re-encoding or moving any existing face; coding settings (quantizer, I-cube spacing,
// motion source) are the file's. Rules:
//   - the database must have the file's face size, depth mode and up axis, and the same
//     grid origin and spacing (within a relative 1e-9); the grid grows to the union of
//     both grids' dims. Cells already in the file are skipped, whatever the database
//     holds for them.
//   - existing cells keep their frame type and references. A new cell is an I-cube when
//     the placement rules (spatial/placement.h) over the union of old and new cells make
//     it one, or when no I-cube (old or new) is in its reach; otherwise a B-cube
//     predicted from one or two I-cubes in reach, old or new: those that see most of it
//     when the database holds the depth of each of them, else the nearest (docs/format.md). Old I-faces used as
//     references are decoded from the file, which gives exactly the encoder's reconstruction.
//   - the new faces are appended, then the new index (cells in (y, z, x) order, frames
//     renumbered) is committed in place (ContainerUpdater). A failure or a kill at any
//     point leaves the file opening as exactly the old database.
// Nothing to add is not an error (cells_added 0, the file untouched). Errors name the
// mismatch, cell, face or file at fault. Progress counts the faces added.
SVC_API Result<AddSummary> add_to_database(const std::filesystem::path& svc_file,
                                           const std::filesystem::path& db_dir,
                                           const AddSettings& settings = AddSettings{},
                                           const EncodeProgress& progress = {});

// Quantizer index used for a quality (1..100, clamped): round((100 - quality) * 255 / 99),
// so every quality step moves the index by 2 or 3 (a step 4.5 to 6.7 % finer).
SVC_API int qindex_for_quality(int quality);

}  // namespace svc
