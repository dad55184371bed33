// SPDX-License-Identifier: BSD-2-Clause
// Replays the fuzzers' seed corpus (tests/fuzz/corpus) through the fuzz entry points, and
// generates that corpus: with SVC_WRITE_FUZZ_CORPUS=DIR set, FuzzCorpus.Generate writes
// the seeds into DIR/container and DIR/frame (the committed corpus was made with
//   SVC_WRITE_FUZZ_CORPUS=tests/fuzz/corpus build/bin/svc_integration_tests --gtest_filter=FuzzCorpus.Generate
// ). Inputs the fuzzers found are added beside the seeds by hand.
//
// The container seeds seed-*.svc are what the current encoder writes (index version 6,
// bare face chunks, depth chunks for the stored-depth seed). Beside them, index-vN-*.svc
// are files written in index version N = 4 or 5, which readers still read (their pixels
// are pinned in svc_pinned_output_test.cc), and old-index-vN-*.svc files whose index is in
// version N = 1, 2 or 3 (FACE chunks in the version 2 and 1 files), which readers no
// longer read: each must be refused, not crash. Generate writes neither.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <map>

#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/depth_encoder.h"
#include "codec/encoder/intra_encoder.h"
#include "container/container.h"
#include "fuzz/fuzz_entry.h"
#include "fuzz/reader_entry.h"
#include "scene/scene.h"
#include "support/reference_hints.h"
#include "support/test_support.h"
#include "svc/encoder.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

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
// encoder (index version 6).
std::map<std::string, std::vector<uint8_t>> container_seeds(const fs::path& work) {
  std::map<std::string, std::vector<uint8_t>> seeds;
  struct Variant {
    std::string name;
    std::array<int, 3> grid;
    bool intra_only;
    MotionSearch motion;
    bool stored_depth = false;
  };
  const Variant variants[] = {
      {"seed-2x1x2-ib-depth.svc", {2, 1, 2}, false, MotionSearch::kDepth},
      {"seed-3x1x1-ib-log.svc", {3, 1, 1}, false, MotionSearch::kLogarithmic},
      {"seed-1x1x1-intra.svc", {1, 1, 1}, true, MotionSearch::kDepth},
      {"seed-3x1x1-ib-stored-depth.svc", {3, 1, 1}, false, MotionSearch::kDepth, true},
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
    settings.depth = v.stored_depth;
    settings.depth_max_error = v.stored_depth ? 3 : 0;
    const fs::path out = work / v.name;
    auto summary = encode_database(db, out, settings);
    EXPECT_TRUE(summary.ok()) << summary.status().to_string();
    seeds[v.name] = testing::read_file_data(out);
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
      const std::vector<uint8_t> b =
          codec::encode_b_frame(source, ref0, refs == 2 ? &ref1 : nullptr,
                                codec::candidate_hints(candidates, candidates, &warp, refs == 2 ? &warp : nullptr),
                                params, nullptr, nullptr);
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
    // Depth planes (docs/codec.md section 8): on their own, and predicted from the
    // synthetic reference planes decode_depth_input gives.
    const std::vector<uint16_t> depth = fuzz::synthetic_depth(w, h, 2);
    seeds["seed-depth-intra-" + size] =
        fuzz::make_frame_input(3, w, h, codec::encode_depth(depth, w, h, 0, nullptr).payload);
    const std::vector<uint16_t> plane0 = fuzz::synthetic_depth(w, h, 0), plane1 = fuzz::synthetic_depth(w, h, 1);
    const Camera camera0 = fuzz::synthetic_depth_camera(0), camera1 = fuzz::synthetic_depth_camera(1),
                 target = fuzz::synthetic_depth_camera(2);
    const codec::DepthReference references[] = {{plane0.data(), &camera0}, {plane1.data(), &camera1}};
    codec::DepthPrediction prediction;
    codec::predict_depth(references, target, w, h, &prediction);
    seeds["seed-depth-inter-" + size] =
        fuzz::make_frame_input(3, w, h, codec::encode_depth(depth, w, h, 2, &prediction).payload);
  }
  return seeds;
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
    const std::vector<uint8_t> bytes = testing::read_file_data(path);
    const int decoded = fuzz::run_container_input(bytes);
    // Seeds are intact files: every face decodes. Files with an older index are refused.
    const std::string name = path.filename().string();
    if (name.rfind("seed-", 0) == 0) EXPECT_GT(decoded, 0);
    if (name.rfind("old-index-v", 0) == 0) EXPECT_EQ(decoded, 0);
  }
}

// The threads target's check (tests/fuzz/reader_entry.h) on every container seed: four
// threads, prefetch, small caches and a close part-way, against the sequential decode.
std::atomic<int> g_thread_failures{0};
void count_thread_failure(const std::string& what) {
  if (g_thread_failures++ < 10) ADD_FAILURE() << what;
}

TEST(FuzzCorpus, ReplaysContainerCorpusThroughTheThreadsEntry) {
  fuzz::g_failure_handler = &count_thread_failure;
  int succeeded = 0;
  for (const fs::path& path : corpus_files("container")) {
    SCOPED_TRACE(path.string());
    succeeded += fuzz::run_threads_input(testing::read_file_data(path));
  }
  fuzz::g_failure_handler = nullptr;
  EXPECT_EQ(g_thread_failures.load(), 0);
  EXPECT_GT(succeeded, 0);
}

TEST(FuzzCorpus, ReplaysFrameCorpus) {
  const auto files = corpus_files("frame");
  ASSERT_FALSE(files.empty());
  for (const fs::path& path : files) {
    SCOPED_TRACE(path.string());
    const int decoded = fuzz::run_frame_input(testing::read_file_data(path));
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
  for (const auto& [name, bytes] : container_seeds(dir.path())) write(fs::path(target) / "container" / name, bytes);
  for (const auto& [name, bytes] : frame_seeds()) write(fs::path(target) / "frame" / name, bytes);
}

}  // namespace
}  // namespace svc
