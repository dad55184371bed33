// SPDX-License-Identifier: BSD-2-Clause
// Sharded encoding (svc encode --shard K/N, svc merge): merged parts equal the
// one-process encode byte for byte, and wrong, missing, duplicate or damaged parts are
// refused with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "common/bytes.h"
#include "output/part_file.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using testing::read_file_bytes;

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A 7x1x5 grid of 16-pixel faces ("full"), the same grid with holes (sparse.json in the
// same folder: every cell with (x + 2z) % 3 == 1 left out) and another scene.
class Shard : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-shard");
    samples::SceneOptions options;
    options.grid = {7, 1, 5};
    options.face_size = 16;
    ASSERT_TRUE(samples::generate_scene(options, full()).ok());
    std::ifstream in(full() / "manifest.json");
    json manifest = json::parse(in);
    json cells = json::array();
    for (const json& cell : manifest["cells"]) {
      if ((cell["index"][0].get<int>() + 2 * cell["index"][2].get<int>()) % 3 != 1) cells.push_back(cell);
    }
    manifest["cells"] = cells;
    write_text(sparse(), manifest.dump(1));
    options.seed = 2;
    options.grid = {4, 1, 3};
    ASSERT_TRUE(samples::generate_scene(options, other()).ok());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path full() { return dir_->path() / "full"; }
  static fs::path sparse() { return full() / "sparse.json"; }
  static fs::path other() { return dir_->path() / "other"; }
  static fs::path out(const std::string& name) { return dir_->path() / name; }

  static EncoderSettings settings(int threads) {
    EncoderSettings s;
    s.threads = threads;
    return s;
  }

  // Encodes the N parts of `db` (named tag-K-of-N.part) and returns their paths.
  static std::vector<fs::path> encode_parts(const fs::path& db, int n, const std::string& tag,
                                            const EncoderSettings& s = settings(1)) {
    std::vector<fs::path> parts;
    for (int k = 1; k <= n; ++k) {
      parts.push_back(out(tag + "-" + std::to_string(k) + "-of-" + std::to_string(n) + ".part"));
      auto summary = encode_shard(db, parts.back(), s, k, n);
      EXPECT_TRUE(summary.ok()) << summary.status().to_string();
    }
    return parts;
  }

  // Merging `parts` fails with a message holding `expected`, and `target` keeps the
  // bytes it had.
  static void expect_refused(const std::vector<fs::path>& parts, const std::string& expected) {
    const fs::path target = out("refused.svc");
    write_text(target, "earlier output");
    auto merged = merge_shards(parts, target);
    ASSERT_FALSE(merged.ok());
    EXPECT_NE(merged.status().message().find(expected), std::string::npos) << merged.status().to_string();
    EXPECT_EQ(read_file_bytes(target), "earlier output");
    for (const auto& entry : fs::directory_iterator(dir_->path())) {
      EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    }
  }

  static testing::TempDir* dir_;
};

testing::TempDir* Shard::dir_ = nullptr;

TEST_F(Shard, MergedPartsEqualOneProcessEncodeForAnyShardCount) {
  for (const fs::path& db : {full(), sparse()}) {
    const fs::path whole = out("whole.svc");
    ASSERT_TRUE(encode_database(db, whole, settings(2)).ok());
    const std::string expected = read_file_bytes(whole);
    ASSERT_FALSE(expected.empty());
    for (int n : {1, 2, 3, 7}) {
      std::vector<fs::path> parts = encode_parts(db, n, "p");
      // Parts finish in any order: merge them reversed and rotated.
      std::reverse(parts.begin(), parts.end());
      std::rotate(parts.begin(), parts.begin() + n / 2, parts.end());
      const fs::path merged = out("merged.svc");
      auto summary = merge_shards(parts, merged);
      ASSERT_TRUE(summary.ok()) << summary.status().to_string();
      EXPECT_EQ(summary->parts, static_cast<uint64_t>(n));
      EXPECT_TRUE(read_file_bytes(merged) == expected) << db << " in " << n << " shards differs";
    }
  }
}

// With depth each face's depth chunk travels with it: the merge gives the full encode's
// bytes.
TEST_F(Shard, DepthMergesToTheOneProcessEncode) {
  EncoderSettings s = settings(1);
  s.depth = true;
  s.depth_max_error = 3;
  const fs::path whole = out("whole-depth.svc");
  ASSERT_TRUE(encode_database(full(), whole, s).ok());
  const std::vector<fs::path> parts = encode_parts(full(), 3, "depth", s);
  const fs::path merged = out("merged-depth.svc");
  auto summary = merge_shards(parts, merged);
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_TRUE(read_file_bytes(merged) == read_file_bytes(whole));
}

TEST_F(Shard, EveryFaceIsCodedByExactlyOneShard) {
  const std::vector<fs::path> parts = encode_parts(full(), 3, "count");
  std::vector<int> coded;
  for (const fs::path& path : parts) {
    auto part = open_part(path);
    ASSERT_TRUE(part.ok()) << part.status().to_string();
    coded.resize(part->descriptor.plan.frames.size(), 0);
    for (const PartFace& face : part->descriptor.faces) ++coded.at(face.frame);
  }
  EXPECT_EQ(coded.size(), 7u * 5u * 6u);
  EXPECT_EQ(std::count(coded.begin(), coded.end(), 1), static_cast<long>(coded.size()));
}

TEST_F(Shard, MissingDuplicateAndForeignPartsAreRefused) {
  const std::vector<fs::path> parts = encode_parts(full(), 3, "ok");
  expect_refused({parts[0], parts[2]}, "part(s) 2 of 3 missing");
  expect_refused({parts[0], parts[1], parts[1], parts[2]}, "as is");

  const std::vector<fs::path> other_db = encode_parts(other(), 3, "other");
  expect_refused({parts[0], other_db[1], parts[2]}, "different database");

  EncoderSettings coarse = settings(1);
  coarse.quality = 40;
  const std::vector<fs::path> other_settings = encode_parts(full(), 3, "coarse", coarse);
  expect_refused({parts[0], other_settings[1], parts[2]}, "encoded with");

  const std::vector<fs::path> halves = encode_parts(full(), 2, "halves");
  expect_refused({parts[0], halves[1], parts[2]}, "a part of 2");

  ASSERT_TRUE(encode_database(full(), out("not-a-part.svc"), settings(1)).ok());
  expect_refused({out("not-a-part.svc")}, "not a part file");
  expect_refused({}, "no part files");
}

TEST_F(Shard, DamagedOrTruncatedPartsAreRefused) {
  const std::vector<fs::path> parts = encode_parts(full(), 2, "damage");
  std::string bytes = read_file_bytes(parts[1]);
  // A byte inside the first face chunk's payload.
  std::string flipped = bytes;
  flipped[kPartHeaderSize + 20] ^= 0x40;
  write_text(out("flipped.part"), flipped);
  expect_refused({parts[0], out("flipped.part")}, "CRC");

  write_text(out("cut.part"), bytes.substr(0, bytes.size() / 2));
  expect_refused({parts[0], out("cut.part")}, "cut.part");
  expect_refused({parts[0], out("no-such.part")}, "no-such.part");
}

TEST_F(Shard, PartsOfAnotherVersionAreRefused) {
  const std::vector<fs::path> parts = encode_parts(full(), 2, "version");
  std::string bytes = read_file_bytes(parts[0]);
  // The PART chunk: tag, size, then the version string's length and text.
  ByteReader trailer({reinterpret_cast<const uint8_t*>(bytes.data()) + bytes.size() - kPartTrailerSize, 8});
  const uint64_t part_at = trailer.u64();
  const uint64_t version_at = part_at + 12 + 4;
  bytes[version_at] = bytes[version_at] == '9' ? '8' : '9';
  const uint64_t chunk_end = bytes.size() - kPartTrailerSize;
  const std::span<const uint8_t> chunk(reinterpret_cast<const uint8_t*>(bytes.data()) + part_at,
                                       chunk_end - part_at - 4);
  const uint32_t crc = crc32_of(chunk);
  for (int i = 0; i < 4; ++i) bytes[chunk_end - 4 + i] = static_cast<char>(crc >> (8 * i));
  write_text(out("old.part"), bytes);
  expect_refused({out("old.part"), parts[1]}, "written by svc");
}

TEST_F(Shard, ACancelledShardLeavesNoPartAndRunsAgainAlone) {
  const fs::path part = out("rerun-2-of-2.part");
  auto cancelled = encode_shard(full(), part, settings(1), 2, 2, [](uint64_t done, uint64_t) { return done < 5; });
  ASSERT_FALSE(cancelled.ok());
  EXPECT_EQ(cancelled.status().code(), ErrorCode::kCancelled);
  EXPECT_FALSE(fs::exists(part));
  ASSERT_TRUE(encode_shard(full(), part, settings(2), 2, 2).ok());
  ASSERT_TRUE(encode_shard(full(), out("rerun-1-of-2.part"), settings(1), 1, 2).ok());
  ASSERT_TRUE(merge_shards({part, out("rerun-1-of-2.part")}, out("rerun.svc")).ok());
  ASSERT_TRUE(encode_database(full(), out("rerun-whole.svc"), settings(1)).ok());
  EXPECT_TRUE(read_file_bytes(out("rerun.svc")) == read_file_bytes(out("rerun-whole.svc")));
}

TEST_F(Shard, ShardNumbersOutsideTheRangeAreRefused) {
  for (auto [k, n] : std::vector<std::pair<int, int>>{{0, 3}, {4, 3}, {1, 0}, {1, kMaxShards + 1}}) {
    auto result = encode_shard(full(), out("bad.part"), settings(1), k, n);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), ErrorCode::kInvalidArgument);
    EXPECT_FALSE(fs::exists(out("bad.part")));
  }
}

// Every speed, switched-off tool, quantization matrix, fixed B-face offset and cube border shards:
// the merge gives the one-process encode's bytes at the same settings.
TEST_F(Shard, EverySpeedAndToolSettingMergesToTheOneProcessEncode) {
  std::vector<std::pair<std::string, EncoderSettings>> variants;
  for (int speed = 1; speed <= kMaxEncoderSpeed; ++speed) {
    EncoderSettings s = settings(1);
    ASSERT_TRUE(apply_encoder_speed(&s, speed).ok());
    variants.emplace_back("speed" + std::to_string(speed), s);
  }
  EncoderSettings tuned = settings(1);
  ASSERT_TRUE(disable_coding_tool(&tuned.tools, "cdef").ok());
  tuned.tools.weighted_quant_matrix = true;
  tuned.b_qindex_offset = 30;
  tuned.cube_border_units = 2;
  variants.emplace_back("tuned", tuned);
  for (const auto& [tag, s] : variants) {
    const fs::path whole = out(tag + "-whole.svc");
    ASSERT_TRUE(encode_database(full(), whole, s).ok());
    const std::vector<fs::path> parts = encode_parts(full(), 2, tag, s);
    const fs::path merged = out(tag + "-merged.svc");
    auto summary = merge_shards(parts, merged);
    ASSERT_TRUE(summary.ok()) << tag << ": " << summary.status().to_string();
    EXPECT_TRUE(read_file_bytes(merged) == read_file_bytes(whole)) << tag;
  }
}

// Parts coded with different tools, quantization matrices, B-face offsets or cube borders would merge
// into a file no single encode gives: refused, naming both settings.
TEST_F(Shard, PartsOfDifferentToolSettingsAreRefused) {
  const std::vector<fs::path> plain = encode_parts(full(), 2, "plain");
  EncoderSettings fast = settings(1);
  ASSERT_TRUE(apply_encoder_speed(&fast, 3).ok());
  fast.layout = CubeLayout::kVisibility;  // the same plan: only the tools differ
  const std::vector<fs::path> quick = encode_parts(full(), 2, "quick", fast);
  expect_refused({plain[0], quick[1]}, "--disable-tool rdoq");
  expect_refused({quick[0], plain[1]}, "the default settings");
  EncoderSettings offset = settings(1);
  offset.b_qindex_offset = 30;
  const std::vector<fs::path> fixed = encode_parts(full(), 2, "fixed", offset);
  expect_refused({plain[0], fixed[1]}, "--b-qindex-offset 30");
  EncoderSettings weighted = settings(1);
  weighted.tools.weighted_quant_matrix = true;
  const std::vector<fs::path> matrix = encode_parts(full(), 2, "matrix", weighted);
  expect_refused({matrix[0], plain[1]}, "--quant-matrix weighted");
  EncoderSettings narrow = settings(1);
  narrow.cube_border_units = 1;
  const std::vector<fs::path> border = encode_parts(full(), 2, "border", narrow);
  expect_refused({plain[0], border[1]}, "--cube-border 1");
}

}  // namespace
}  // namespace svc
