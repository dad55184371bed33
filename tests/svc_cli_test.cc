// SPDX-License-Identifier: BSD-2-Clause
// The svc tool as a user runs it: what it prints, its exit codes, and what it refuses
// to write. Runs the built build/bin/svc.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

using testing::CliRun;
using testing::quoted;
using testing::run_program;

CliRun run_svc(const std::string& args, const fs::path& dir = fs::temp_directory_path()) {
  return run_program("svc", args, dir);
}

class Cli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-cli");
    samples::SceneOptions options;
    options.grid = {2, 1, 1};
    options.face_size = 16;
    ASSERT_TRUE(samples::generate_scene(options, db()).ok());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path db() { return dir_->path() / "db"; }
  static fs::path work(const std::string& name) { return dir_->path() / name; }

  static testing::TempDir* dir_;
};
testing::TempDir* Cli::dir_ = nullptr;

TEST_F(Cli, EncodeReportsTheBytesOfEachSyntaxElement) {
  const fs::path scene = work("syntax-scene");
  samples::SceneOptions options;
  options.grid = {3, 1, 1};
  options.face_size = 64;
  ASSERT_TRUE(samples::generate_scene(options, scene).ok());
  const fs::path file = work("syntax.svc");
  const CliRun run = run_svc("encode --quiet --json --qindex 60 " + quoted(scene) + " -o " + quoted(file));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json parsed = json::parse(run.output, nullptr, false);
  ASSERT_FALSE(parsed.is_discarded()) << run.output;
  const std::vector<std::string> names = syntax_element_names();
  ASSERT_EQ(names.size(), kSyntaxElementCount);
  for (const char* type : {"intra", "predicted"}) {
    const json& bytes = parsed["syntax_bytes"][type];
    ASSERT_EQ(bytes.size(), names.size()) << bytes;
    double sum = 0;
    for (const std::string& name : names) {
      ASSERT_TRUE(bytes.contains(name)) << name;
      EXPECT_GE(bytes[name].get<double>(), 0) << name;
      sum += bytes[name].get<double>();
    }
    const double payload = parsed["face_types"][type]["bytes"].get<double>();
    ASSERT_GT(payload, 0) << type;
    EXPECT_NEAR(sum, payload, 0.02 * payload) << type << ": " << bytes;
    EXPECT_GT(bytes["levels"].get<double>(), 0) << type;
    EXPECT_GT(bytes["modes"].get<double>(), 0) << type;
  }
  EXPECT_GT(parsed["syntax_bytes"]["predicted"]["vectors"].get<double>(), 0);
  // The B-faces' quantizer index the trial chose (docs/encoder.md 5).
  EXPECT_GE(parsed["b_qindex"].get<int>(), 60 + 26);
  EXPECT_LE(parsed["b_qindex"].get<int>(), 60 + 42);
  // How close the references came: the inter macroblocks' screened prediction is a PSNR
  // (or null when no macroblock of that kind), warped ones at most the inter ones.
  const json& prediction = parsed["prediction"];
  const json& predicted_mbs = parsed["face_types"]["predicted"]["macroblocks"];
  const uint64_t inter_mbs = predicted_mbs["forward"].get<uint64_t>() + predicted_mbs["backward"].get<uint64_t>() +
                             predicted_mbs["bidirectional"].get<uint64_t>() +
                             predicted_mbs["skipped"].get<uint64_t>();
  ASSERT_GT(inter_mbs, 0u);
  EXPECT_LE(prediction["macroblocks_warped"].get<uint64_t>(), inter_mbs);
  ASSERT_TRUE(prediction["screened_psnr_y"]["inter"].is_number()) << prediction;
  EXPECT_GT(prediction["screened_psnr_y"]["inter"].get<double>(), 15.0) << prediction;
  EXPECT_LT(prediction["screened_psnr_y"]["inter"].get<double>(), 99.0) << prediction;
  if (predicted_mbs["intra"].get<uint64_t>() == 0) EXPECT_TRUE(prediction["screened_psnr_y"]["intra"].is_null());
  // The text summary shows them with --verbose only.
  const std::string encode = "encode --no-progress -y " + quoted(scene) + " -o " + quoted(file);
  EXPECT_EQ(run_svc(encode).output.find("syntax:"), std::string::npos);
  const CliRun verbose = run_svc(encode + " --verbose");
  EXPECT_NE(verbose.output.find("I-faces   syntax: header"), std::string::npos) << verbose.output;
  EXPECT_NE(verbose.output.find("B-faces   syntax: header"), std::string::npos) << verbose.output;
  EXPECT_NE(verbose.output.find("B-faces   closest inter prediction PSNR-Y"), std::string::npos) << verbose.output;
}

TEST_F(Cli, InfoOfAQindexFileShowsTheIndexAndNoQuality) {
  const fs::path file = work("qindex.svc");
  ASSERT_EQ(run_svc("encode --quiet --qindex 20 " + quoted(db()) + " -o " + quoted(file)).exit_code, 0);
  const CliRun info = run_svc("info " + quoted(file));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("quantizer index 20"), std::string::npos) << info.output;
  EXPECT_EQ(info.output.find("quality"), std::string::npos) << info.output;
  const CliRun json = run_svc("info --json " + quoted(file));
  EXPECT_NE(json.output.find("\"quality\": null"), std::string::npos) << json.output;
  EXPECT_NE(json.output.find("\"qindex\": 20"), std::string::npos) << json.output;

  const fs::path by_quality = work("quality.svc");
  ASSERT_EQ(run_svc("encode --quiet -q 60 " + quoted(db()) + " -o " + quoted(by_quality)).exit_code, 0);
  const CliRun quality_info = run_svc("info " + quoted(by_quality));
  EXPECT_NE(quality_info.output.find("quality 60, quantizer index " + std::to_string(qindex_for_quality(60))),
            std::string::npos)
      << quality_info.output;
}

// The highest speed takes the regular layout unless --layout says otherwise; -v names
// the layout and the tools switched off.
TEST_F(Cli, SpeedSetsTheLayoutAndAnExplicitLayoutWins) {
  const fs::path file = work("speed.svc");
  const std::string encode = "encode -v -y " + quoted(db()) + " -o " + quoted(file);
  const std::string fastest = " --speed " + std::to_string(kMaxEncoderSpeed);
  const CliRun by_speed = run_svc(encode + fastest);
  ASSERT_EQ(by_speed.exit_code, 0) << by_speed.output;
  EXPECT_NE(by_speed.output.find(", regular layout,"), std::string::npos) << by_speed.output;
  EXPECT_NE(by_speed.output.find("tools off: "), std::string::npos) << by_speed.output;
  for (const std::string& name : speed_disabled_tools(kMaxEncoderSpeed))
    EXPECT_NE(by_speed.output.find(name), std::string::npos) << name << "\n" << by_speed.output;
  const CliRun overridden = run_svc(encode + fastest + " --layout visibility");
  ASSERT_EQ(overridden.exit_code, 0) << overridden.output;
  EXPECT_NE(overridden.output.find(", visibility layout,"), std::string::npos) << overridden.output;
  const CliRun plain = run_svc(encode);
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_NE(plain.output.find(", visibility layout,"), std::string::npos) << plain.output;
  EXPECT_EQ(plain.output.find("tools off"), std::string::npos) << plain.output;
  const CliRun regular = run_svc(encode + " --layout regular --disable-tool cdef");
  ASSERT_EQ(regular.exit_code, 0) << regular.output;
  EXPECT_NE(regular.output.find(", regular layout,"), std::string::npos) << regular.output;
  EXPECT_NE(regular.output.find("tools off: cdef"), std::string::npos) << regular.output;
}

// A file with depth decodes to a database whose depth EXRs hold the decoded depth: it
// passes svc check, and encoding it again with --depth keeps every depth code.
TEST_F(Cli, DepthRoundTripsThroughDecodeAndEncode) {
  const fs::path file = work("depth.svc"), decoded = work("depth-decoded"), again = work("depth-again.svc");
  ASSERT_EQ(run_svc("encode --quiet --depth " + quoted(db()) + " -o " + quoted(file)).exit_code, 0);
  const CliRun info = run_svc("info " + quoted(file));
  EXPECT_NE(info.output.find("maximum error 0 (inverse-depth codes)"), std::string::npos) << info.output;
  ASSERT_EQ(run_svc("decode --quiet " + quoted(file) + " -o " + quoted(decoded)).exit_code, 0);
  EXPECT_TRUE(fs::exists(decoded / "cells" / "0_0_0" / "px.exr"));
  EXPECT_FALSE(fs::exists(decoded / "depth-unknown.exr"));
  ASSERT_EQ(run_svc("check " + quoted(decoded)).exit_code, 0);
  ASSERT_EQ(run_svc("encode --quiet --depth " + quoted(decoded) + " -o " + quoted(again)).exit_code, 0);
  auto first = Reader::open(file), second = Reader::open(again);
  ASSERT_TRUE(first.ok() && second.ok());
  for (const CellEntry& cell : (*first)->cells()) {
    for (Face face : kAllFaces) {
      auto a = (*first)->decode_face_depth(cell.index, face), b = (*second)->decode_face_depth(cell.index, face);
      ASSERT_TRUE(a.ok() && b.ok());
      EXPECT_TRUE(*a == *b) << face_label(cell.index, face);
    }
  }
  const CliRun bad =
      run_svc("encode --quiet --depth --depth-max-error 256 " + quoted(db()) + " -o " + quoted(work("bad.svc")));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--depth-max-error"), std::string::npos) << bad.output;
}

TEST_F(Cli, OutputToStandardOutputIsRefused) {
  const fs::path cwd = work("stdout");
  fs::create_directories(cwd);
  const fs::path file = work("for-stdout.svc");
  ASSERT_EQ(run_svc("encode --quiet " + quoted(db()) + " -o " + quoted(file)).exit_code, 0);
  const std::vector<std::string> commands = {
      "encode " + quoted(db()) + " -o -",
      "decode " + quoted(file) + " -o -",
      "inspect " + quoted(file) + " --cell 0,0,0 --face px -o -",
  };
  for (const std::string& command : commands) {
    const CliRun run = run_svc(command, cwd);
    EXPECT_EQ(run.exit_code, 2) << command;
    EXPECT_EQ(run.output.rfind("svc: ", 0), 0u) << run.output;
    EXPECT_NE(run.output.find("standard output"), std::string::npos) << command << "\n" << run.output;
    EXPECT_FALSE(fs::exists(cwd / "-")) << command;
  }
}

// Every usage error the parser catches exits 2 with a "svc: " message; the codes are in --help.
TEST_F(Cli, UsageErrorsExitTwoWithThePrefix) {
  const std::vector<std::string> usage_errors = {
      "",        // no subcommand
      "encode",  // missing DB_DIR
      "encode " + quoted(db()) + " -o x.svc --no-such-option",
      "encode " + quoted(db()) + " -o x.svc --motion sideways",
      "encode " + quoted(db()) + " -o x.svc -q 101",
      "encode " + quoted(db()) + " -o x.svc --threads -1",
      "decode a.svc -o out --cell 1,2",
  };
  for (const std::string& args : usage_errors) {
    const CliRun run = run_svc(args);
    EXPECT_EQ(run.exit_code, 2) << "svc " << args << "\n" << run.output;
    EXPECT_EQ(run.output.rfind("svc: ", 0), 0u) << "svc " << args << "\n" << run.output;
  }
  const CliRun not_a_number = run_svc("encode " + quoted(db()) + " -o x.svc -q abc");
  EXPECT_EQ(not_a_number.exit_code, 2);
  EXPECT_NE(not_a_number.output.find("'abc' is not a whole number"), std::string::npos) << not_a_number.output;
  const CliRun help = run_svc("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("2 usage error"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("3 damaged .svc file"), std::string::npos) << help.output;
  // A damaged file: 3; a missing one: 1.
  EXPECT_EQ(run_svc("info /no/such/file.svc").exit_code, 1);
  const fs::path damaged = work("damaged.svc");
  std::ofstream(damaged) << "not an svc file at all, just some text long enough to be read";
  EXPECT_EQ(run_svc("info " + quoted(damaged)).exit_code, 3);
}

TEST_F(Cli, SceneToolFollowsTheSameCodes) {
  for (const std::string& args : {std::string("--no-such-option x"), std::string(""), std::string("--kind cave x"),
                                  std::string("--face-size abc x")}) {
    const CliRun run = run_program("svc-scene", args, dir_->path());
    EXPECT_EQ(run.exit_code, 2) << "svc-scene " << args << "\n" << run.output;
    EXPECT_EQ(run.output.rfind("svc-scene: ", 0), 0u) << "svc-scene " << args << "\n" << run.output;
  }
  EXPECT_NE(run_program("svc-scene", "--help", dir_->path()).output.find("2 usage error"), std::string::npos);
}

// An existing output is kept unless -y; with -y it is replaced.
TEST_F(Cli, ExistingOutputsAreKeptUnlessOverwriteIsGiven) {
  const fs::path file = work("kept.svc");
  std::ofstream(file) << "precious";
  const CliRun refused = run_svc("encode --quiet " + quoted(db()) + " -o " + quoted(file));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_EQ(refused.output.rfind("svc: ", 0), 0u) << refused.output;
  EXPECT_NE(refused.output.find("-y"), std::string::npos) << refused.output;
  EXPECT_EQ(testing::read_file_bytes(file), "precious");
  ASSERT_EQ(run_svc("encode --quiet -y " + quoted(db()) + " -o " + quoted(file)).exit_code, 0);
  EXPECT_NE(testing::read_file_bytes(file), "precious");

  // decode into a non-empty folder.
  const fs::path folder = work("decoded");
  fs::create_directories(folder);
  std::ofstream(folder / "notes.txt") << "mine";
  EXPECT_EQ(run_svc("decode --quiet " + quoted(file) + " -o " + quoted(folder)).exit_code, 2);
  EXPECT_FALSE(fs::exists(folder / "manifest.json"));
  ASSERT_EQ(run_svc("decode --quiet -y " + quoted(file) + " -o " + quoted(folder)).exit_code, 0);
  EXPECT_TRUE(fs::exists(folder / "manifest.json"));
  EXPECT_EQ(testing::read_file_bytes(folder / "notes.txt"), "mine");
  // An empty folder is written into without -y.
  const fs::path empty = work("empty");
  fs::create_directories(empty);
  EXPECT_EQ(run_svc("decode --quiet " + quoted(file) + " -o " + quoted(empty)).exit_code, 0);

  // inspect onto an existing PNG.
  const fs::path png = work("mb.png");
  std::ofstream(png) << "old png";
  EXPECT_EQ(run_svc("inspect " + quoted(file) + " --cell 0,0,0 --face px -o " + quoted(png)).exit_code, 2);
  EXPECT_EQ(testing::read_file_bytes(png), "old png");
  EXPECT_EQ(run_svc("inspect -y " + quoted(file) + " --cell 0,0,0 --face px -o " + quoted(png)).exit_code, 0);
  EXPECT_NE(testing::read_file_bytes(png), "old png");

  // demo --keep into a non-empty folder.
  EXPECT_EQ(run_svc("demo --keep " + quoted(folder)).exit_code, 2);
  // bench --out (when the tool is built with the benchmark): refused before any work.
  if (run_svc("bench --help").exit_code == 0) {
    const CliRun bench = run_svc("bench " + quoted(db()) + " --out " + quoted(folder));
    EXPECT_EQ(bench.exit_code, 2) << bench.output;
    EXPECT_FALSE(fs::exists(folder / "work"));
    EXPECT_FALSE(fs::exists(folder / "results.json"));
    EXPECT_EQ(run_svc("bench -y " + quoted(db()) + " --out " + quoted(db())).exit_code, 2);
  }
}

// The input is never written over, not even with -y.
TEST_F(Cli, TheInputIsNeverOverwritten) {
  const fs::path scene = work("own-scene");
  fs::copy(db(), scene, fs::copy_options::recursive);
  const std::string manifest = testing::read_file_bytes(scene / "manifest.json");
  const CliRun onto_manifest =
      run_svc("encode --quiet -y " + quoted(scene) + " -o " + quoted(scene / "manifest.json"));
  EXPECT_EQ(onto_manifest.exit_code, 2) << onto_manifest.output;
  EXPECT_NE(onto_manifest.output.find("input"), std::string::npos) << onto_manifest.output;
  EXPECT_EQ(testing::read_file_bytes(scene / "manifest.json"), manifest);
  // A new file inside the database folder is no input: allowed.
  ASSERT_EQ(run_svc("encode --quiet " + quoted(scene) + " -o " + quoted(scene / "scene.svc")).exit_code, 0);

  // Decoding into the folder that holds the .svc (and the source images).
  const fs::path png = scene / "cells" / "0_0_0" / "px.png";
  const std::string source_png = testing::read_file_bytes(png);
  const CliRun onto_source = run_svc("decode --quiet -y " + quoted(scene / "scene.svc") + " -o " + quoted(scene));
  EXPECT_EQ(onto_source.exit_code, 2) << onto_source.output;
  EXPECT_EQ(testing::read_file_bytes(png), source_png);
  // inspect onto its own input.
  const fs::path svc_file = scene / "scene.svc";
  const std::string svc_bytes = testing::read_file_bytes(svc_file);
  EXPECT_EQ(run_svc("inspect -y " + quoted(svc_file) + " --cell 0,0,0 --face px -o " + quoted(svc_file)).exit_code,
            2);
  EXPECT_EQ(testing::read_file_bytes(svc_file), svc_bytes);
  // A relative spelling of the same path is the same input.
  EXPECT_EQ(run_svc("encode --quiet -y own-scene -o own-scene/./manifest.json", dir_->path()).exit_code, 2);
  EXPECT_EQ(testing::read_file_bytes(scene / "manifest.json"), manifest);
}

TEST_F(Cli, SceneToolKeepsANonEmptyFolderUnlessOverwriteIsGiven) {
  const fs::path out = work("scene-out");
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine";
  const std::string args = quoted(out) + " --grid 1,1,1 --face-size 16 --quiet";
  const CliRun refused = run_program("svc-scene", args, dir_->path());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_EQ(refused.output.rfind("svc-scene: ", 0), 0u) << refused.output;
  EXPECT_FALSE(fs::exists(out / "manifest.json"));
  EXPECT_EQ(run_program("svc-scene", "-y " + args, dir_->path()).exit_code, 0);
  EXPECT_TRUE(fs::exists(out / "manifest.json"));
}

TEST_F(Cli, ShardsMergeIntoTheEncodeAndBadPartsExitOne) {
  ASSERT_EQ(run_svc("encode " + quoted(db()) + " -o " + quoted(work("whole.svc")) + " --quiet").exit_code, 0);
  for (int k = 1; k <= 2; ++k) {
    const std::string part = quoted(work("part-" + std::to_string(k) + ".svcpart"));
    ASSERT_EQ(run_svc("encode " + quoted(db()) + " --shard " + std::to_string(k) + "/2 -o " + part + " --quiet")
                  .exit_code,
              0);
  }
  const std::string parts = quoted(work("part-2.svcpart")) + " " + quoted(work("part-1.svcpart"));
  ASSERT_EQ(run_svc("merge " + parts + " -o " + quoted(work("merged.svc"))).exit_code, 0);
  EXPECT_EQ(testing::read_file_bytes(work("merged.svc")), testing::read_file_bytes(work("whole.svc")));

  const CliRun missing = run_svc("merge " + quoted(work("part-1.svcpart")) + " -o " + quoted(work("half.svc")));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("part(s) 2 of 2 missing"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(work("half.svc")));
  // The merge keeps an existing output without -y (a usage error, as for encode), and
  // never writes over a part.
  EXPECT_EQ(run_svc("merge " + parts + " -o " + quoted(work("merged.svc"))).exit_code, 2);
  const std::string part_before = testing::read_file_bytes(work("part-1.svcpart"));
  EXPECT_NE(run_svc("merge " + parts + " -o " + quoted(work("part-1.svcpart")) + " -y").exit_code, 0);
  EXPECT_EQ(testing::read_file_bytes(work("part-1.svcpart")), part_before);
  for (const char* shard : {"0/2", "3/2", "1", "a/b", "1/0"}) {
    EXPECT_EQ(
        run_svc("encode " + quoted(db()) + " --shard " + shard + " -o " + quoted(work("x.svcpart"))).exit_code, 2)
        << shard;
  }
}

}  // namespace
}  // namespace svc
