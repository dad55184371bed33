// SPDX-License-Identifier: BSD-2-Clause
// Random access through the reader's caches: bit-exact against a sequential decode
// without caches, byte budgets never exceeded, counters that say what happened, and the
// prefetch order.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "codec/common/intra_frame.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/intra_encoder.h"
#include "common/file_io.h"
#include "container/container.h"
#include "reader/face_decode.h"
#include "reader/prefetch_order.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

ReaderSettings uncached_settings() {
  ReaderSettings settings;
  settings.coefficient_cache_bytes = 0;
  settings.face_cache_bytes = 0;
  settings.reference_cache_bytes = 0;
  settings.prefetch_threads = 0;
  return settings;
}

bool same_image(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  return a.width == b.width && a.height == b.height && a.y == b.y && a.cb == b.cb && a.cr == b.cr;
}

// A 6x1x3 hall (I-cubes at x = 1, 4 and z = 1), encoded once for the whole file, and
// every face decoded sequentially without caches as the reference.
class ReaderAccess : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-reader-access");
    samples::SceneOptions options;
    options.grid = {6, 1, 3};
    options.face_size = 48;
    ASSERT_TRUE(samples::generate_scene(options, dir_->path() / "db").ok());
    EncoderSettings encoder;
    encoder.threads = 1;
    auto summary = encode_database(dir_->path() / "db", file(), encoder);
    ASSERT_TRUE(summary.ok()) << summary.status().to_string();
    auto reader = Reader::open(file(), uncached_settings());
    ASSERT_TRUE(reader.ok()) << reader.status().to_string();
    reference_ = new std::vector<ImageYCbCr420>();
    for (const CellEntry& cell : (*reader)->cells()) {
      for (Face face : kAllFaces) {
        auto image = (*reader)->decode_face_ycbcr(cell.index, face);
        ASSERT_TRUE(image.ok()) << image.status().to_string();
        reference_->push_back(std::move(image).value());
      }
    }
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete dir_;
  }
  static fs::path file() { return dir_->path() / "hall.svc"; }
  static const ImageYCbCr420& reference(size_t frame) { return (*reference_)[frame]; }
  // A B-face and the frames of its references.
  static std::pair<size_t, std::vector<size_t>> some_b_face(const Reader& reader, size_t skip = 0) {
    for (size_t c = 0; c < reader.cells().size(); ++c) {
      const FaceEntry& entry = reader.cells()[c].faces[0];
      // Two reference cubes: two reference faces (of the face's own direction), plus with
      // cube references the adjacent faces of each cube whose border it reads.
      const auto own_direction =
          std::count_if(entry.references.begin(), entry.references.end(),
                        [](const auto& dependency) { return dependency.second == Face::kPX; });
      if (entry.type != FaceType::kPredicted || own_direction != 2) continue;
      if (skip-- > 0) continue;
      std::vector<size_t> refs;
      for (const auto& [cell, face] : entry.references) refs.push_back(cell * kFaceCount + static_cast<int>(face));
      return {c * kFaceCount, refs};
    }
    return {SIZE_MAX, {}};
  }

  // Two B-faces (first, second) that need the same frames `refs` (the same references
  // and the same border edges of each), or SIZE_MAX.
  struct SharedDependencies {
    size_t first = SIZE_MAX, second = SIZE_MAX;
    std::vector<size_t> refs;
  };
  static SharedDependencies b_faces_sharing_dependencies(const Reader& reader) {
    for (size_t i = 0;; ++i) {
      auto [first, refs] = some_b_face(reader, i);
      if (first == SIZE_MAX) return {};
      for (size_t j = i + 1;; ++j) {
        auto [second, second_refs] = some_b_face(reader, j);
        if (second == SIZE_MAX) break;
        if (second_refs == refs) return {first, second, refs};
      }
    }
  }

  static testing::TempDir* dir_;
  static std::vector<ImageYCbCr420>* reference_;
};
testing::TempDir* ReaderAccess::dir_ = nullptr;
std::vector<ImageYCbCr420>* ReaderAccess::reference_ = nullptr;

TEST_F(ReaderAccess, RandomOrderThroughSmallCachesEqualsSequentialDecode) {
  const uint64_t face_bytes = 48 * 48 + 2 * 24 * 24 + 256;  // about one decoded face with bookkeeping
  ReaderSettings settings;
  settings.face_cache_bytes = 5 * face_bytes;
  settings.coefficient_cache_bytes = 6000;  // a few I-faces: forces evictions
  settings.prefetch_threads = 0;
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  const auto& cells = (*reader)->cells();
  ASSERT_EQ(cells.size(), 18u);

  std::vector<size_t> order;
  for (int pass = 0; pass < 3; ++pass) {
    for (size_t f = 0; f < cells.size() * kFaceCount; ++f) order.push_back(f);
  }
  std::mt19937 rng(7);
  std::shuffle(order.begin(), order.end(), rng);
  for (size_t frame : order) {
    const CellIndex& cell = cells[frame / kFaceCount].index;
    const Face face = kAllFaces[frame % kFaceCount];
    auto image = (*reader)->decode_face_ycbcr(cell, face);
    ASSERT_TRUE(image.ok()) << image.status().to_string();
    ASSERT_TRUE(same_image(*image, reference(frame))) << "frame " << frame;
    const ReaderStats stats = (*reader)->stats();
    ASSERT_LE(stats.face_cache.bytes_held, settings.face_cache_bytes);
    ASSERT_LE(stats.coefficient_cache.bytes_held, settings.coefficient_cache_bytes);
  }
  const ReaderStats stats = (*reader)->stats();
  EXPECT_LE(stats.face_cache.peak_bytes, settings.face_cache_bytes);
  EXPECT_LE(stats.coefficient_cache.peak_bytes, settings.coefficient_cache_bytes);
  EXPECT_GT(stats.face_cache.evictions, 0u);
  EXPECT_GT(stats.coefficient_cache.evictions, 0u);
  EXPECT_GT(stats.face_cache.hits, 0u);
  EXPECT_EQ(stats.face_cache.hits + stats.face_cache.misses, order.size());
  EXPECT_EQ(stats.face_cache.in_flight_waits, 0u);
  EXPECT_EQ(stats.face_cache.budget_bytes, settings.face_cache_bytes);

  // RGB goes through the same pixels.
  auto uncached = Reader::open(file(), uncached_settings());
  ASSERT_TRUE(uncached.ok());
  for (size_t c : {0u, 7u, 17u}) {
    auto a = (*reader)->decode_cube(cells[c].index);
    auto b = (*uncached)->decode_cube(cells[c].index);
    ASSERT_TRUE(a.ok() && b.ok());
    for (int f = 0; f < kFaceCount; ++f) {
      EXPECT_EQ((*a)[f].pixels, (*b)[f].pixels);
      EXPECT_EQ((*a)[f].pixels.size(), 48u * 48u * 3u);
    }
  }
}

TEST_F(ReaderAccess, CachedReferencesSkipEntropyDecodingAndCachedFacesSkipReads) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = 1;  // the counts below are one thread's; more decode references first
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok());
  const auto [first, second, refs] = b_faces_sharing_dependencies(**reader);
  ASSERT_NE(second, SIZE_MAX) << "no two B-faces that need the same faces";
  const auto& cells = (*reader)->cells();

  auto face = (*reader)->decode_face_ycbcr(cells[first / kFaceCount].index, Face::kPX);
  ASSERT_TRUE(face.ok());
  EXPECT_TRUE(same_image(*face, reference(first)));
  // Exactly the faces the index lists are read and entropy-decoded: the two reference
  // faces and, with cube references, the adjacent faces of both reference cubes whose
  // border the face reads.
  ASSERT_GE(refs.size(), 2u);
  ReaderStats stats = (*reader)->stats();
  EXPECT_EQ(stats.intra_faces_parsed, refs.size());
  EXPECT_EQ(stats.predicted_faces_decoded, 1u);
  EXPECT_EQ(stats.chunks_read, refs.size() + 1);
  EXPECT_EQ(stats.coefficient_cache.misses, refs.size());
  EXPECT_EQ(stats.coefficient_cache.entries, refs.size());
  const uint64_t bytes_after_first = stats.bytes_read;
  uint64_t expected_bytes = cells[first / kFaceCount].faces[0].coded_bytes + (refs.size() + 1) * kBareChunkOverhead;
  for (size_t ref : refs) expected_bytes += cells[ref / kFaceCount].faces[ref % kFaceCount].coded_bytes;
  EXPECT_EQ(bytes_after_first, expected_bytes);

  // Another B-face that needs the same I-faces: only its own chunk is read and only its
  // own bytes are entropy-decoded.
  face = (*reader)->decode_face_ycbcr(cells[second / kFaceCount].index, Face::kPX);
  ASSERT_TRUE(face.ok());
  EXPECT_TRUE(same_image(*face, reference(second)));
  stats = (*reader)->stats();
  EXPECT_EQ(stats.intra_faces_parsed, refs.size());
  EXPECT_EQ(stats.predicted_faces_decoded, 2u);
  EXPECT_EQ(stats.chunks_read, refs.size() + 2);
  // Both references come padded from the reference cache: nothing reconstructed again.
  EXPECT_EQ(stats.reference_cache.hits, 2u);
  EXPECT_EQ(stats.coefficient_cache.hits, 0u);

  // The same face again: no read, no decode, a face-cache hit; the shared image is the
  // cached one and outlives close().
  auto shared = (*reader)->acquire_face_ycbcr(cells[second / kFaceCount].index, Face::kPX);
  ASSERT_TRUE(shared.ok());
  stats = (*reader)->stats();
  EXPECT_EQ(stats.chunks_read, refs.size() + 2);
  EXPECT_EQ(stats.predicted_faces_decoded, 2u);
  EXPECT_EQ(stats.face_cache.hits, 1u);
  auto again = (*reader)->acquire_face_ycbcr(cells[second / kFaceCount].index, Face::kPX);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(shared->get(), again->get());
  (*reader)->close();
  EXPECT_TRUE(same_image(**shared, reference(second)));
  EXPECT_EQ((*reader)->stats().face_cache.bytes_held, 0u);
  EXPECT_EQ((*reader)->stats().coefficient_cache.bytes_held, 0u);
}

// Without the reference cache, a second B-face needing the same faces reconstructs them
// again, from the semi-decoded I-faces: no chunk is read or entropy-decoded twice.
TEST_F(ReaderAccess, WithoutAReferenceCacheReferencesComeFromSemiDecodedIFaces) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.reference_cache_bytes = 0;
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok());
  const auto [first, second, refs] = b_faces_sharing_dependencies(**reader);
  ASSERT_NE(second, SIZE_MAX) << "no two B-faces that need the same faces";
  const auto& cells = (*reader)->cells();
  for (size_t frame : {first, second}) {
    auto face = (*reader)->decode_face_ycbcr(cells[frame / kFaceCount].index, Face::kPX);
    ASSERT_TRUE(face.ok()) << face.status().to_string();
    EXPECT_TRUE(same_image(*face, reference(frame)));
  }
  const ReaderStats stats = (*reader)->stats();
  EXPECT_EQ(stats.intra_faces_parsed, refs.size());
  EXPECT_EQ(stats.chunks_read, refs.size() + 2);
  EXPECT_EQ(stats.coefficient_cache.hits, refs.size());
  EXPECT_EQ(stats.reference_cache.entries, 0u);
  EXPECT_EQ(stats.reference_cache.peak_bytes, 0u);
}

// A cell's random access: its six faces decode from the faces of at most its two
// reference cubes (cube references add adjacent faces, never another cube), each
// I-face parsed once, and every face equals the sequential decode.
TEST_F(ReaderAccess, CellDecodesFromAtMostItsTwoReferenceCubes) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok());
  const auto [b_frame, refs] = some_b_face(**reader, 0);
  ASSERT_NE(b_frame, SIZE_MAX);
  const size_t cell = b_frame / kFaceCount;
  const CellEntry& entry = (*reader)->cells()[cell];
  std::set<size_t> cubes, faces;
  for (const FaceEntry& face : entry.faces) {
    for (const auto& [ref_cell, ref_face] : face.references) {
      cubes.insert(ref_cell);
      faces.insert(ref_cell * kFaceCount + static_cast<size_t>(ref_face));
    }
  }
  EXPECT_EQ(cubes.size(), 2u);
  EXPECT_EQ(faces.size(), 12u);  // both reference cubes whole
  for (size_t f : faces) EXPECT_EQ((*reader)->cells()[f / kFaceCount].faces[f % kFaceCount].type, FaceType::kIntra);
  for (int f = 0; f < kFaceCount; ++f) {
    auto face = (*reader)->decode_face_ycbcr(entry.index, static_cast<Face>(f));
    ASSERT_TRUE(face.ok()) << face.status().to_string();
    EXPECT_TRUE(same_image(*face, reference(cell * kFaceCount + f))) << "face " << f;
  }
  const ReaderStats stats = (*reader)->stats();
  EXPECT_EQ(stats.intra_faces_parsed, faces.size());
  EXPECT_EQ(stats.predicted_faces_decoded, 6u);
  EXPECT_EQ(stats.chunks_read, faces.size() + 6);
}

// B-faces list different border edges of the same reference face. One padded across
// more edges serves those that read fewer (docs/codec.md 5.7), so a decode of every
// face in order pads the reference faces fewer times than there are distinct
// (reference, edges) pairs, and every face is still the uncached decode's.
TEST_F(ReaderAccess, AReferencePaddedAcrossMoreEdgesServesBFacesThatReadFewer) {
  auto file_handle = ReadOnlyFile::open(file());
  ASSERT_TRUE(file_handle.ok());
  auto opened = open_container(**file_handle, ReaderLimits{});
  ASSERT_TRUE(opened.ok());
  const ContainerIndex& index = opened->index;
  std::map<uint32_t, std::set<uint8_t>> edges_of_reference;
  size_t intra_faces = 0;
  for (const FrameRecord& record : index.frames) {
    if (record.type == FaceType::kIntra) ++intra_faces;
    if (!record.cube_references) continue;
    for (size_t r = 0; r < record.references.size(); ++r) {
      edges_of_reference[record.references[r]].insert(reference_border_edges(record, r));
    }
  }
  size_t padded_requests = 0;  // distinct (reference, edges) pairs
  for (const auto& [ref, edge_sets] : edges_of_reference) padded_requests += edge_sets.size();
  ASSERT_GT(padded_requests, edges_of_reference.size()) << "every B-face reads the same edges of a reference";

  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = 1;
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok());
  size_t frame = 0;
  for (const CellEntry& cell : (*reader)->cells()) {
    for (Face face : kAllFaces) {
      auto image = (*reader)->decode_face_ycbcr(cell.index, face);
      ASSERT_TRUE(image.ok()) << image.status().to_string();
      EXPECT_TRUE(same_image(*image, reference(frame))) << "frame " << frame;
      ++frame;
    }
  }
  // Each I-face reconstructed once (the budget holds them all), and the padded faces:
  // here at most twice each (first across the faces decoded by then, then across the
  // rest).
  const uint64_t padded = (*reader)->stats().reference_cache.misses - intra_faces;
  EXPECT_LT(padded, padded_requests);
  EXPECT_LE(padded, 2 * edges_of_reference.size());
}

// The payload's reference border (B-face byte 3) and the index's cube-references bit
// must agree: a mismatch is damage, reported with the face, never decoded with the
// wrong references.
TEST_F(ReaderAccess, BorderAndCubeReferencesBitMustAgree) {
  auto file_handle = ReadOnlyFile::open(file());
  ASSERT_TRUE(file_handle.ok());
  auto opened = open_container(**file_handle, ReaderLimits{});
  ASSERT_TRUE(opened.ok());
  ContainerIndex index = opened->index;
  uint32_t b_frame = 0;
  while (index.frames[b_frame].type != FaceType::kPredicted) ++b_frame;
  ASSERT_TRUE(index.frames[b_frame].cube_references);
  ASSERT_TRUE(decode_indexed_face(**file_handle, index, b_frame).ok());

  // A source whose payload of b_frame carries another border.
  class EditedSource : public FileCodedFaceSource {
   public:
    EditedSource(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame, uint8_t border)
        : FileCodedFaceSource(file, index), frame_(frame), border_(border) {}
    Result<std::vector<uint8_t>> payload(uint32_t frame) override {
      SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, FileCodedFaceSource::payload(frame));
      // Header byte 2, bits 0-2 (codec/common/bframe_codec.h).
      if (frame == frame_) {
        bytes[codec::kBFrameReferencesByte] =
            static_cast<uint8_t>((bytes[codec::kBFrameReferencesByte] & ~0x07) | border_);
      }
      return bytes;
    }

   private:
    uint32_t frame_;
    uint8_t border_;
  };
  EditedSource bare(**file_handle, index, b_frame, 0);
  auto decoded = decode_indexed_face(**file_handle, index, b_frame, bare);
  ASSERT_FALSE(decoded.ok());
  EXPECT_EQ(decoded.status().code(), ErrorCode::kCorruptData);
  EXPECT_NE(decoded.status().message().find("reference border of 0 units but the index lists cube references"),
            std::string::npos)
      << decoded.status().message();
  EXPECT_NE(decoded.status().message().find(frame_label(index, b_frame)), std::string::npos);
  EditedSource too_wide(**file_handle, index, b_frame, 7);
  decoded = decode_indexed_face(**file_handle, index, b_frame, too_wide);
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.status().message().find("byte 2"), std::string::npos) << decoded.status().message();
  index.frames[b_frame].cube_references = false;
  decoded = decode_indexed_face(**file_handle, index, b_frame);
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.status().message().find("does not list cube references"), std::string::npos)
      << decoded.status().message();
}

TEST_F(ReaderAccess, ZeroBudgetsCacheNothing) {
  auto reader = Reader::open(file(), uncached_settings());
  ASSERT_TRUE(reader.ok());
  const CellIndex cell = (*reader)->cells()[3].index;
  for (int i = 0; i < 2; ++i) ASSERT_TRUE((*reader)->decode_cube(cell).ok());
  const ReaderStats stats = (*reader)->stats();
  EXPECT_EQ(stats.face_cache.entries, 0u);
  EXPECT_EQ(stats.face_cache.peak_bytes, 0u);
  EXPECT_EQ(stats.coefficient_cache.peak_bytes, 0u);
  EXPECT_EQ(stats.face_cache.hits, 0u);
  EXPECT_EQ(stats.face_cache.misses, 12u);
  EXPECT_EQ(stats.reference_cache.peak_bytes, 0u);
  EXPECT_EQ(stats.reference_cache.hits, 0u);
}

TEST_F(ReaderAccess, SemiDecodedIFacesAreChargedWhatTheyHold) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok());
  auto file_reader = ReadOnlyFile::open(file());
  ASSERT_TRUE(file_reader.ok());
  uint64_t i_faces = 0, expected_bytes = 0, levels = 0, level_bytes = 0;
  for (const CellEntry& cell : (*reader)->cells()) {
    for (Face face : kAllFaces) {
      const FaceEntry& entry = cell.faces[static_cast<int>(face)];
      if (entry.type != FaceType::kIntra) continue;
      ASSERT_TRUE((*reader)->decode_face_ycbcr(cell.index, face).ok());
      ++i_faces;
      // The same payload parsed here: the cache holds exactly this sparse form.
      auto payload = (*file_reader)->read_vector(entry.offset, entry.coded_bytes);  // a bare chunk
      ASSERT_TRUE(payload.ok());
      codec::CoefficientFrame parsed;
      ASSERT_TRUE(codec::parse_intra_frame(*payload, 48, 48, &parsed).ok());
      parsed.levels.shrink_to_fit();
      parsed.block_counts.shrink_to_fit();
      expected_bytes += parsed.memory_bytes() + 96;
      for (uint16_t count : parsed.block_counts) levels += count;
      level_bytes += parsed.levels.size();
    }
  }
  const ReaderStats stats = (*reader)->stats();
  ASSERT_EQ(stats.coefficient_cache.entries, i_faces);
  EXPECT_EQ(stats.coefficient_cache.bytes_held, expected_bytes);
  // Packed levels (a few bits each) plus three bytes a block (mode, count) and the CDEF
  // parameters: on these tiny, busy 48x48 faces well under half of RGB; svc-bench-access
  // reports the 256x256 scenes.
  const double per_face = static_cast<double>(stats.coefficient_cache.bytes_held) / i_faces;
  EXPECT_LT(per_face / (48.0 * 48.0 * 3.0), 0.6) << per_face << " bytes per I-face";
  EXPECT_LT(static_cast<double>(levels) / i_faces, 48.0 * 48.0 * 1.5 / 2) << "not sparse";
  EXPECT_LT(level_bytes, levels) << "levels not packed below a byte each";
}

TEST_F(ReaderAccess, DamagedReferenceFailsItsBFacesOnlyAndIsNotCached) {
  auto clean = Reader::open(file(), uncached_settings());
  ASSERT_TRUE(clean.ok());
  const auto [b_frame, refs] = some_b_face(**clean, 0);
  ASSERT_NE(b_frame, SIZE_MAX);
  const CellEntry& ref_cell = (*clean)->cells()[refs[0] / kFaceCount];
  const fs::path damaged = dir_->path() / "damaged.svc";
  fs::copy_file(file(), damaged, fs::copy_options::overwrite_existing);
  {
    std::fstream out(damaged, std::ios::in | std::ios::out | std::ios::binary);
    out.seekp(static_cast<std::streamoff>(ref_cell.faces[0].offset + 20));
    out.put('\x5a');
  }
  ReaderSettings one_thread;
  one_thread.decode_threads = 1;  // no references decoded ahead: each request reads the damaged one once
  auto reader = Reader::open(damaged, one_thread);
  ASSERT_TRUE(reader.ok());
  const CellIndex b_cell = (*reader)->cells()[b_frame / kFaceCount].index;
  for (int attempt = 0; attempt < 2; ++attempt) {
    auto face = (*reader)->decode_face(b_cell, Face::kPX);
    ASSERT_FALSE(face.ok());
    EXPECT_EQ(face.status().code(), ErrorCode::kCorruptData);
    EXPECT_NE(face.status().message().find("its reference"), std::string::npos) << face.status().message();
    EXPECT_NE(face.status().message().find(std::to_string(ref_cell.faces[0].offset)), std::string::npos);
  }
  EXPECT_EQ((*reader)->stats().coefficient_cache.misses, 2u);  // asked twice, read twice
  auto other = (*reader)->decode_face_ycbcr(b_cell, Face::kNX);
  ASSERT_TRUE(other.ok()) << other.status().to_string();
  EXPECT_TRUE(same_image(*other, reference(b_frame + 1)));
}

// inspect_face decodes the same pixels as decode_face, and its macroblock map is what
// the face's coding says: all intra for an I-face; in B-faces, inter or skipped
// macroblocks somewhere (intra macroblocks predict from their neighbours as I-faces do,
// so a small B-face of this smooth scene may be all intra).
TEST_F(ReaderAccess, InspectFaceGivesDecodedPixelsAndMacroblockModes) {
  auto reader = Reader::open(file());
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  const auto [b_frame, refs] = some_b_face(**reader);
  ASSERT_NE(b_frame, SIZE_MAX);
  for (size_t frame : {b_frame, refs[0]}) {
    const CellEntry& cell = (*reader)->cells()[frame / kFaceCount];
    const Face face = static_cast<Face>(frame % kFaceCount);
    auto inspected = (*reader)->inspect_face(cell.index, face);
    ASSERT_TRUE(inspected.ok()) << inspected.status().to_string();
    auto decoded = (*reader)->decode_face(cell.index, face);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(inspected->image.pixels, decoded->pixels);
    EXPECT_EQ(inspected->type, cell.faces[static_cast<int>(face)].type);
    ASSERT_EQ(inspected->macroblocks_x * inspected->macroblocks_y, 9);  // 48x48 faces
    ASSERT_EQ(inspected->modes.size(), 9u);
    ASSERT_EQ(inspected->partitions.size(), 9u);
    ASSERT_EQ(inspected->warped.size(), 9u);
    for (size_t m = 0; m < 9; ++m) {
      if (!inspected->warped[m]) continue;  // warped: a coded inter macroblock of a B-face
      EXPECT_EQ(inspected->type, FaceType::kPredicted);
      EXPECT_NE(inspected->modes[m], MacroblockCoding::kIntra);
      EXPECT_NE(inspected->modes[m], MacroblockCoding::kSkipped);
    }
    // Only inter macroblocks of a B-face are split.
    for (size_t m = 0; m < 9; ++m) {
      if (inspected->partitions[m] == MacroblockPartition::k16x16) continue;
      EXPECT_EQ(inspected->type, FaceType::kPredicted);
      EXPECT_NE(inspected->modes[m], MacroblockCoding::kIntra);
      EXPECT_NE(inspected->modes[m], MacroblockCoding::kSkipped);
    }
    const auto intra = std::count(inspected->modes.begin(), inspected->modes.end(), MacroblockCoding::kIntra);
    if (inspected->type == FaceType::kIntra) EXPECT_EQ(intra, 9);
  }
  bool some_inter = false;
  for (const CellEntry& cell : (*reader)->cells()) {
    for (int f = 0; f < kFaceCount && !some_inter; ++f) {
      if (cell.faces[f].type != FaceType::kPredicted) continue;
      auto inspected = (*reader)->inspect_face(cell.index, static_cast<Face>(f));
      ASSERT_TRUE(inspected.ok()) << inspected.status().to_string();
      some_inter = std::count(inspected->modes.begin(), inspected->modes.end(), MacroblockCoding::kIntra) < 9;
    }
  }
  EXPECT_TRUE(some_inter);
  auto missing = (*reader)->inspect_face(CellIndex{99, 0, 0}, Face::kPX);
  EXPECT_EQ(missing.status().code(), ErrorCode::kNotFound);
}

TEST_F(ReaderAccess, ErrorsNameWhatIsWrong) {
  ReaderSettings bad;
  bad.prefetch_threads = 65;
  EXPECT_EQ(Reader::open(file(), bad).status().code(), ErrorCode::kInvalidArgument);
  bad = ReaderSettings{};
  bad.prefetch_radius = -1;
  EXPECT_EQ(Reader::open(file(), bad).status().code(), ErrorCode::kInvalidArgument);

  auto reader = Reader::open(file());
  ASSERT_TRUE(reader.ok());
  auto missing = (*reader)->decode_face(CellIndex{9, 0, 0}, Face::kPX);
  EXPECT_EQ(missing.status().code(), ErrorCode::kNotFound);
  EXPECT_NE(missing.status().message().find("cell (9,0,0)"), std::string::npos);
  EXPECT_EQ((*reader)->set_viewer(CellIndex{6, 0, 0}).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ((*reader)->set_viewer(std::array<double, 3>{NAN, 0, 0}).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ((*reader)->set_viewer(CellIndex{1, 0, 1}, {INFINITY, 0, 0}).code(), ErrorCode::kInvalidArgument);
  // A position outside the grid is clamped to the nearest cell.
  EXPECT_TRUE((*reader)->set_viewer(std::array<double, 3>{-100, 0, 100}).ok());

  (*reader)->close();
  (*reader)->close();
  EXPECT_EQ((*reader)->decode_face(CellIndex{0, 0, 0}, Face::kPX).status().code(), ErrorCode::kCancelled);
  EXPECT_EQ((*reader)->decode_cube(CellIndex{0, 0, 0}).status().code(), ErrorCode::kCancelled);
  EXPECT_EQ((*reader)->set_viewer(CellIndex{0, 0, 0}).code(), ErrorCode::kCancelled);
  EXPECT_EQ((*reader)->cells().size(), 18u);
  EXPECT_TRUE((*reader)->find_cell(CellIndex{5, 0, 2}).has_value());
  EXPECT_TRUE((*reader)->wait_for_prefetch(std::chrono::milliseconds(0)));
}

TEST(ReaderPrefetchOrder, NearestRingFirstThenCellsAhead) {
  reader_internal::GridGeometry grid;
  grid.dims = {5, 1, 5};
  grid.spacing = {0.5, 1, 0.5};
  auto find = [&](const CellIndex& c) -> std::optional<size_t> {
    if (c.x == 3 && c.z == 2) return std::nullopt;  // a hole
    return static_cast<size_t>(c.z * 5 + c.x);
  };
  const CellIndex viewer{2, 0, 2};
  const auto centre = grid.centre(viewer);
  // Moving towards -z: the cell behind (2,0,3) comes after every ring-1 cell ahead.
  auto order = reader_internal::prefetch_order(grid, viewer, centre, {0, 0, -1}, 1, 100, find);
  ASSERT_EQ(order.size(), 8u);  // 9 minus the hole
  EXPECT_EQ(order[0], 12u);     // the viewer's own cell
  EXPECT_EQ(order[1], 7u);      // straight ahead (2,0,1)
  EXPECT_TRUE((order[2] == 6u && order[3] == 8u) || (order[2] == 8u && order[3] == 6u));
  EXPECT_EQ(order.back(), 17u);  // straight behind
  // Radius 2 and a cap on the count.
  order = reader_internal::prefetch_order(grid, viewer, centre, {0, 0, 0}, 2, 4, find);
  ASSERT_EQ(order.size(), 4u);
  EXPECT_EQ(order[0], 12u);
  // Clamped lookups at the grid edge.
  EXPECT_EQ(grid.cell_at({-5, 0, 99}), (CellIndex{0, 0, 4}));
  EXPECT_EQ(grid.cell_at({0.74, 0, 0.76}), (CellIndex{1, 0, 2}));
}

}  // namespace
}  // namespace svc
