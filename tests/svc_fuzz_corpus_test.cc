// Replays the fuzzers' seed corpus (tests/fuzz/corpus) through the fuzz entry points, and
// generates that corpus: with SVC_WRITE_FUZZ_CORPUS=DIR set, FuzzCorpus.Generate writes
// the seeds into DIR/container and DIR/frame (the committed corpus was made with
//   SVC_WRITE_FUZZ_CORPUS=tests/fuzz/corpus build/bin/svc_integration_tests --gtest_filter=FuzzCorpus.Generate
// ). Inputs the fuzzers found are added beside the seeds by hand.
//
// The container seeds seed-*.svc are what the current encoder writes (index version 4,
// bare face chunks). Files of the older container stay beside them, so that readers keep
// being exercised on such files: seed-v3index-*.svc, the current seeds with the index
// rewritten in version 3; seed-framed-*.svc (FACE chunks, index version 2, its cells as
// the older encoder wrote them) and their twins seed-v1index-*.svc, the same bytes with
// the index rewritten in version 1. Generate renews their faces with the current
// encoder's, so that every seed decodes whole.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>

#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/intra_encoder.h"
#include "container/container.h"
#include "fuzz/fuzz_entry.h"
#include "scene/scene.h"
#include "support/index_v1.h"
#include "support/index_v2_v3.h"
#include "support/test_support.h"
#include "svc/encoder.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

fs::path corpus_dir(const std::string& target) {
  return fs::path(SVC_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / target;
}

std::vector<fs::path> corpus_files(const std::string& target) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(corpus_dir(target))) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The seeds: named inputs, each valid (every face decodes), encoded by the current
// encoder (index version 3).
std::map<std::string, std::vector<uint8_t>> container_seeds(const fs::path& work) {
  std::map<std::string, std::vector<uint8_t>> seeds;
  struct Variant {
    std::string name;
    std::array<int, 3> grid;
    bool intra_only;
    MotionSearch motion;
  };
  const Variant variants[] = {
      {"seed-2x1x2-ib-depth.svc", {2, 1, 2}, false, MotionSearch::kDepth},
      {"seed-3x1x1-ib-log.svc", {3, 1, 1}, false, MotionSearch::kLogarithmic},
      {"seed-1x1x1-intra.svc", {1, 1, 1}, true, MotionSearch::kDepth},
  };
  for (const Variant& v : variants) {
    samples::SceneOptions options;
    options.grid = v.grid;
    options.face_size = 16;
    const fs::path db = work / (v.name + ".db");
    EXPECT_TRUE(samples::generate_scene(options, db).ok());
    EncoderSettings settings;
    settings.quality = 50;
    settings.intra_only = v.intra_only;
    settings.motion = v.motion;
    settings.threads = 1;
    const fs::path out = work / v.name;
    auto summary = encode_database(db, out, settings);
    EXPECT_TRUE(summary.ok()) << summary.status().to_string();
    seeds[v.name] = read_bytes(out);
  }
  return seeds;
}

std::map<std::string, std::vector<uint8_t>> frame_seeds() {
  std::map<std::string, std::vector<uint8_t>> seeds;
  const std::pair<int, int> sizes[] = {{16, 16}, {1, 1}, {17, 9}, {33, 20}, {64, 64}};
  for (const auto& [w, h] : sizes) {
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    // A source near the references: shifted and brightened, so the B-frame coder uses
    // inter modes as well as intra ones.
    ImageYCbCr420 source = fuzz::synthetic_reference(w, h, 0);
    for (size_t i = 0; i < source.y.size(); ++i) {
      source.y[i] = static_cast<uint8_t>(std::min(255, source.y[(i + 1) % source.y.size()] + 9));
    }
    for (int q : {64, 200}) {
      const std::vector<uint8_t> intra = codec::encode_intra_frame(source, codec::CodingParams{q}, nullptr);
      seeds["seed-intra-" + size + "-q" + std::to_string(q)] = fuzz::make_frame_input(0, w, h, intra);
    }
    const ImageYCbCr420 ref0 = fuzz::synthetic_reference(w, h, 0);
    const ImageYCbCr420 ref1 = fuzz::synthetic_reference(w, h, 1);
    const int mbs = ((w + 15) / 16) * ((h + 15) / 16);
    codec::FaceCandidates candidates(static_cast<size_t>(mbs), codec::CandidateList{{2, 0}, {0, -2}});
    codec::WarpField warp;
    warp.nodes_x = (w + 15) / 16 + 1;
    warp.nodes_y = (h + 15) / 16 + 1;
    warp.nodes.assign(static_cast<size_t>(warp.nodes_x) * warp.nodes_y, codec::WarpNode{4, -3});
    for (int refs : {1, 2}) {
      codec::BFrameParams params;
      params.qindex = 147;
      const std::vector<uint8_t> b = codec::encode_b_frame(source, ref0, refs == 2 ? &ref1 : nullptr, candidates,
                                                           candidates, &warp, refs == 2 ? &warp : nullptr, params,
                                                           nullptr, nullptr);
      seeds["seed-b" + std::to_string(refs) + "-" + size] =
          fuzz::make_frame_input(static_cast<uint8_t>(refs), w, h, b);
      // The same with epipolar lines (docs/codec.md 3.8).
      const std::array<codec::ReferenceHints, 2> hints = {codec::ReferenceHints{&candidates, nullptr, &warp,
                                                                                codec::EpipolarLines{1, -1, 0}},
                                                          codec::ReferenceHints{&candidates, nullptr, &warp,
                                                                                codec::EpipolarLines{-1, 2, 1}}};
      const std::vector<uint8_t> lines =
          codec::encode_b_frame(source, ref0, refs == 2 ? &ref1 : nullptr, hints, params, nullptr, nullptr);
      seeds["seed-b" + std::to_string(refs) + "-lines-" + size] =
          fuzz::make_frame_input(static_cast<uint8_t>(refs), w, h, lines);
    }
  }
  return seeds;
}

// The committed seeds of the encoder before bare face chunks (index version 2).
std::vector<fs::path> framed_seeds() {
  std::vector<fs::path> seeds;
  for (const fs::path& path : corpus_files("container")) {
    if (path.filename().string().rfind("seed-framed-", 0) == 0) seeds.push_back(path);
  }
  return seeds;
}

// The bytes' container, opened through a scratch file (the readers take files).
struct OpenedBytes {
  std::unique_ptr<ReadOnlyFile> file;
  OpenedContainer container;
};
std::optional<OpenedBytes> open_bytes(const std::vector<uint8_t>& bytes, const fs::path& scratch) {
  {
    std::ofstream out(scratch, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  auto file = ReadOnlyFile::open(scratch);
  EXPECT_TRUE(file.ok()) << scratch;
  if (!file.ok()) return std::nullopt;
  auto opened = open_container(**file, ReaderLimits{});
  EXPECT_TRUE(opened.ok()) << opened.status().to_string();
  if (!opened.ok()) return std::nullopt;
  return OpenedBytes{std::move(*file), std::move(*opened)};
}

// `bytes` (a file whose last chunk is its index) with the index rewritten by `writer`:
// the same header and face chunks, the new INDX chunk in place of the old one, committed
// in slot 0 as generation 1.
std::vector<uint8_t> reindexed(const std::vector<uint8_t>& bytes, const fs::path& scratch,
                               std::vector<uint8_t> (*writer)(const ContainerIndex&)) {
  auto bytes_file = open_bytes(bytes, scratch);
  if (!bytes_file) return {};
  const OpenedContainer* opened = &bytes_file->container;
  EXPECT_EQ(opened->index_offset + opened->index_chunk_size, bytes.size()) << "the index is not the last chunk";
  std::vector<uint8_t> out(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(opened->index_offset));
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, writer(opened->index));
  const std::vector<uint8_t> slot = make_commit_slot(1, opened->index_offset, chunk.size());
  std::copy(slot.begin(), slot.end(), out.begin() + kFileHeaderSize);
  std::fill(out.begin() + kFileHeaderSize + kCommitSlotSize, out.begin() + kPreludeSize, 0);
  out.insert(out.end(), chunk.begin(), chunk.end());
  return out;
}

// The framed seed `framed` with the faces of `current`, the current encoder's file of the
// same scene and settings: the header, cameras and cells of `framed`'s index (its bytes up
// to the frame records) kept, `current`'s frame records and payloads in FACE chunks, the
// index committed in slot 0 as generation 1.
std::vector<uint8_t> renewed_framed_seed(const std::vector<uint8_t>& framed, const std::vector<uint8_t>& current,
                                         const fs::path& work) {
  auto old_file = open_bytes(framed, work / "framed.svc");
  auto new_file = open_bytes(current, work / "current.svc");
  if (!old_file || !new_file) return {};
  const OpenedContainer& old_container = old_file->container;
  ContainerIndex index = new_file->container.index;
  ContainerIndex old_scene = old_container.index;
  old_scene.frames = index.frames;
  old_scene.stats = index.stats;
  EXPECT_EQ(serialize_index(old_scene), serialize_index(index))
      << "the two files hold different scenes or settings";
  auto old_payload = read_chunk(*old_file->file, old_container.index_offset, old_container.index_chunk_size,
                                kIndexChunkTag, "index");
  EXPECT_TRUE(old_payload.ok()) << old_payload.status().to_string();
  if (!old_payload.ok()) return {};
  const std::vector<uint8_t> old_frames = testing::serialize_frames_v2_v3(old_container.index, 2);
  EXPECT_TRUE(old_payload->size() > old_frames.size() &&
              std::equal(old_frames.begin(), old_frames.end(), old_payload->end() - old_frames.size()))
      << "the framed seed's index does not end in version 2 frame records";
  std::vector<uint8_t> out(framed.begin(), framed.begin() + kFileHeaderSize);
  out.resize(kPreludeSize, 0);
  for (FrameRecord& frame : index.frames) {
    auto payload = read_frame_payload(*new_file->file, frame, "face");
    EXPECT_TRUE(payload.ok()) << payload.status().to_string();
    if (!payload.ok()) return {};
    frame.chunk_offset = out.size();
    frame.bare_chunk = false;
    const std::vector<uint8_t> chunk = make_chunk(kFaceChunkTag, *payload);
    out.insert(out.end(), chunk.begin(), chunk.end());
  }
  std::vector<uint8_t> index_payload(old_payload->begin(), old_payload->end() - old_frames.size());
  const std::vector<uint8_t> frames = testing::serialize_frames_v2_v3(index, 2);
  index_payload.insert(index_payload.end(), frames.begin(), frames.end());
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, index_payload);
  const std::vector<uint8_t> slot = make_commit_slot(1, out.size(), chunk.size());
  std::copy(slot.begin(), slot.end(), out.begin() + kFileHeaderSize);
  out.insert(out.end(), chunk.begin(), chunk.end());
  return out;
}

// seed-framed-NAME's current twin seed-NAME.
std::string current_twin(const fs::path& framed_seed) {
  return "seed-" + framed_seed.filename().string().substr(std::string("seed-framed-").size());
}

TEST(FuzzCorpus, FramedSeedsHoldTheCurrentEncodersFaces) {
  testing::TempDir dir("svc-fuzz-framed");
  const auto current = container_seeds(dir.path());
  for (const fs::path& seed : framed_seeds()) {
    SCOPED_TRACE(seed.string() + " (renew with SVC_WRITE_FUZZ_CORPUS, see the top of this file)");
    const std::vector<uint8_t> framed = read_bytes(seed);
    ASSERT_TRUE(current.count(current_twin(seed))) << "no current seed " << current_twin(seed);
    EXPECT_EQ(framed, renewed_framed_seed(framed, current.at(current_twin(seed)), dir.path()));
    auto opened = open_bytes(framed, dir.path() / "seed.svc");
    ASSERT_TRUE(opened);
    EXPECT_EQ(fuzz::run_container_input(framed), static_cast<int>(opened->container.index.frames.size()))
        << "not every face decodes";
  }
}

// seed-framed-NAME's twin seed-v1index-NAME.
fs::path version_one_twin(const fs::path& framed_seed) {
  return framed_seed.parent_path() /
         ("seed-v1index-" + framed_seed.filename().string().substr(std::string("seed-framed-").size()));
}

TEST(FuzzCorpus, VersionOneTwinsAreTheFramedSeedsWithAVersionOneIndex) {
  testing::TempDir dir("svc-fuzz-twins");
  const std::vector<fs::path> seeds = framed_seeds();
  ASSERT_GE(seeds.size(), 3u);
  for (const fs::path& seed : seeds) {
    SCOPED_TRACE(seed.string());
    const std::vector<uint8_t> v2 = read_bytes(seed), v1 = read_bytes(version_one_twin(seed));
    ASSERT_FALSE(v1.empty()) << "missing " << version_one_twin(seed);
    EXPECT_EQ(v1, reindexed(v2, dir.path() / "scratch.svc", &testing::serialize_index_v1));
    auto old_file = ReadOnlyFile::open(version_one_twin(seed));
    auto new_file = ReadOnlyFile::open(seed);
    ASSERT_TRUE(old_file.ok() && new_file.ok());
    auto old_index = open_container(**old_file, ReaderLimits{});
    auto new_index = open_container(**new_file, ReaderLimits{});
    ASSERT_TRUE(old_index.ok()) << old_index.status().to_string();
    ASSERT_TRUE(new_index.ok()) << new_index.status().to_string();
    EXPECT_EQ(v1[old_index->index_offset + 12], 1);
    EXPECT_EQ(v2[new_index->index_offset + 12], 2);
    EXPECT_GT(v1.size(), v2.size());
    // Version 1 has no cube-reference bit; everything else survives.
    ContainerIndex without_cube = new_index->index;
    for (FrameRecord& frame : without_cube.frames) frame.cube_references = false;
    EXPECT_EQ(serialize_index(old_index->index), serialize_index(without_cube));
  }
}

TEST(FuzzCorpus, SeedsDecodeThroughTheEntryPoints) {
  testing::TempDir dir("svc-fuzz-seeds");
  for (const auto& [name, bytes] : container_seeds(dir.path())) {
    ASSERT_FALSE(bytes.empty()) << name;
    auto file = ReadOnlyFile::open(dir.path() / name);
    ASSERT_TRUE(file.ok());
    auto opened = open_container(**file, fuzz::fuzz_limits());
    ASSERT_TRUE(opened.ok()) << opened.status().to_string();
    EXPECT_EQ(fuzz::run_container_input(bytes), static_cast<int>(opened->index.frames.size())) << name;
    // Repairing the checksums of an intact file changes nothing.
    std::vector<uint8_t> copy = bytes;
    EXPECT_FALSE(fuzz::repair_checksums(copy)) << name;
  }
  for (const auto& [name, bytes] : frame_seeds()) {
    EXPECT_EQ(fuzz::run_frame_input(bytes), 1) << name;
  }
}

TEST(FuzzCorpus, RepairedChecksumsLetDamageReachTheParsers) {
  testing::TempDir dir("svc-fuzz-repair");
  auto seeds = container_seeds(dir.path());
  std::vector<uint8_t> bytes = seeds.at("seed-1x1x1-intra.svc");
  bytes[kPreludeSize + 20] ^= 0x40;  // inside the first face's payload
  EXPECT_TRUE(fuzz::repair_checksums(bytes));
  std::vector<uint8_t> again = bytes;
  EXPECT_FALSE(fuzz::repair_checksums(again));
  EXPECT_EQ(again, bytes);
}

TEST(FuzzCorpus, ReplaysContainerCorpus) {
  const auto files = corpus_files("container");
  ASSERT_FALSE(files.empty());
  for (const fs::path& path : files) {
    SCOPED_TRACE(path.string());
    const std::vector<uint8_t> bytes = read_bytes(path);
    const int decoded = fuzz::run_container_input(bytes);
    // Seeds are intact files: every face decodes.
    if (path.filename().string().rfind("seed-", 0) == 0) EXPECT_GT(decoded, 0);
  }
}

TEST(FuzzCorpus, ReplaysFrameCorpus) {
  const auto files = corpus_files("frame");
  ASSERT_FALSE(files.empty());
  for (const fs::path& path : files) {
    SCOPED_TRACE(path.string());
    const int decoded = fuzz::run_frame_input(read_bytes(path));
    if (path.filename().string().rfind("seed-", 0) == 0) EXPECT_EQ(decoded, 1);
  }
}

TEST(FuzzCorpus, Generate) {
  const char* target = std::getenv("SVC_WRITE_FUZZ_CORPUS");
  if (target == nullptr) GTEST_SKIP() << "set SVC_WRITE_FUZZ_CORPUS=DIR to write the seed corpus";
  testing::TempDir dir("svc-fuzz-generate");
  auto write = [](const fs::path& path, const std::vector<uint8_t>& bytes) {
    fs::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    ASSERT_TRUE(out.good()) << path;
  };
  // Container seeds; the framed seeds and their version 1 twins renewed from them.
  const auto current = container_seeds(dir.path());
  for (const auto& [name, bytes] : current) {
    write(fs::path(target) / "container" / name, bytes);
    write(fs::path(target) / "container" / ("seed-v3index-" + name.substr(std::string("seed-").size())),
          reindexed(bytes, dir.path() / "scratch.svc", &testing::serialize_index_v3));
  }
  for (const fs::path& seed : framed_seeds()) {
    const std::vector<uint8_t> framed =
        renewed_framed_seed(read_bytes(seed), current.at(current_twin(seed)), dir.path());
    ASSERT_FALSE(framed.empty()) << seed;
    write(fs::path(target) / "container" / seed.filename(), framed);
    write(fs::path(target) / "container" / version_one_twin(seed).filename(),
          reindexed(framed, dir.path() / "scratch.svc", &testing::serialize_index_v1));
  }
  for (const auto& [name, bytes] : frame_seeds()) write(fs::path(target) / "frame" / name, bytes);
}

}  // namespace
}  // namespace svc
