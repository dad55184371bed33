// SPDX-License-Identifier: BSD-2-Clause
// The svc tool's conventions as a user meets them: interrupts leave nothing behind,
// --json everywhere with one vocabulary, --threads that change nothing but speed, input
// checks (check, outside paths, damaged images) that speak with svc's voice alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include "database/database.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/metrics.h"
#include "svc/reader.h"

extern char** environ;

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using testing::CliRun;
using testing::quoted;
using testing::run_program;

class CliConventions : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-cli-conventions");
    samples::SceneOptions options;
    options.grid = {3, 1, 3};
    options.face_size = 32;
    options.threads = 2;
    ASSERT_TRUE(samples::generate_scene(options, db()).ok());
    ASSERT_EQ(svc("encode --quiet " + quoted(db()) + " -o " + quoted(file())).exit_code, 0);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static CliRun svc(const std::string& args) { return run_program("svc", args, dir_->path()); }
  static fs::path db() { return dir_->path() / "db"; }
  static fs::path file() { return dir_->path() / "db.svc"; }
  static fs::path work(const std::string& name) { return dir_->path() / name; }
  // A copy of the database to damage.
  static fs::path copy_of_db(const std::string& name) {
    const fs::path copy = work(name);
    fs::copy(db(), copy, fs::copy_options::recursive);
    return copy;
  }
  // No ".NAME.tmp-PID" or ".NAME.old-PID" beside an output.
  static void expect_no_staging_left(const fs::path& folder, const std::string& prefix) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      EXPECT_NE(entry.path().filename().string().rfind(prefix + ".", 0), 0u) << entry.path() << " left behind";
    }
  }
  static json parse_json(const CliRun& run) {
    const json parsed = json::parse(run.output, nullptr, false);
    EXPECT_FALSE(parsed.is_discarded()) << run.output;
    return parsed;
  }

  // The JSON in the output of a run that also wrote errors (stderr comes with stdout).
  static json parse_json_after_errors(const CliRun& run) {
    const size_t start = run.output.find("{\n"), end = run.output.find("\n}");
    EXPECT_TRUE(start != std::string::npos && end != std::string::npos && start < end) << run.output;
    if (start == std::string::npos || end == std::string::npos || start > end) return json();
    return parse_json(CliRun{run.exit_code, run.output.substr(start, end + 2 - start)});
  }

  static testing::TempDir* dir_;
};
testing::TempDir* CliConventions::dir_ = nullptr;

// Every command's --json is JSON alone on stdout, names the command, and uses one
// vocabulary: face types are "intra" and "predicted" in encode and info alike.
TEST_F(CliConventions, JsonOnEveryCommandWithOneVocabulary) {
  const CliRun encode = svc("encode --json -y " + quoted(db()) + " -o " + quoted(work("j.svc")));
  ASSERT_EQ(encode.exit_code, 0) << encode.output;
  const json e = parse_json(encode);
  const CliRun info = svc("info --json " + quoted(work("j.svc")));
  const json i = parse_json(info);
  EXPECT_EQ(e["command"], "encode");
  EXPECT_EQ(i["command"], "info");
  for (const char* type : {"intra", "predicted"}) {
    EXPECT_EQ(e["face_types"][type]["bytes"], i["face_types"][type]["bytes"]) << type;
    EXPECT_EQ(e["face_types"][type]["faces"], i["face_types"][type]["faces"]) << type;
  }
  EXPECT_EQ(e["file_bytes"], i["file_bytes"]);
  // The per-cell table adds up to the bytes by face type.
  uint64_t cell_bytes = 0;
  for (const json& cell : i["per_cell"]) {
    uint64_t faces = 0;
    for (const auto& [face, bytes] : cell["face_bytes"].items()) faces += bytes.get<uint64_t>();
    EXPECT_EQ(cell["bytes"].get<uint64_t>(), faces);
    EXPECT_TRUE(cell["type"] == "intra" || cell["type"] == "predicted") << cell;
    cell_bytes += faces;
  }
  EXPECT_EQ(cell_bytes, i["face_types"]["intra"]["bytes"].get<uint64_t>() +
                            i["face_types"]["predicted"]["bytes"].get<uint64_t>());
  EXPECT_EQ(i["per_cell"].size(), 9u);

  const std::vector<std::pair<std::string, std::string>> commands = {
      {"verify", "verify --json " + quoted(file())},
      {"check", "check --json " + quoted(db())},
      {"decode", "decode --json " + quoted(file()) + " -o " + quoted(work("json-decoded"))},
      {"inspect", "inspect --json " + quoted(file()) + " --cell 0,0,0 --face px -o " + quoted(work("j.png"))},
  };
  for (const auto& [name, args] : commands) {
    const CliRun run = svc(args);
    EXPECT_EQ(run.exit_code, 0) << args << "\n" << run.output;
    EXPECT_EQ(parse_json(run)["command"], name) << run.output;
  }
  // The human summary of info lists every cell.
  const CliRun table = svc("info " + quoted(file()));
  EXPECT_NE(table.output.find("(1,0,1)"), std::string::npos) << table.output;
}

// --quiet prints nothing on success; progress is drawn only when asked for outside a
// terminal, and the line is cleared at the end.
TEST_F(CliConventions, QuietAndProgress) {
  EXPECT_EQ(svc("verify --quiet " + quoted(file())).output, "");
  EXPECT_EQ(svc("encode --quiet -y " + quoted(db()) + " -o " + quoted(work("q.svc"))).output, "");
  const CliRun plain = svc("verify " + quoted(file()));
  EXPECT_EQ(plain.output.find('\r'), std::string::npos) << "progress drawn into a pipe";
  const CliRun forced = svc("verify --progress " + quoted(file()));
  EXPECT_NE(forced.output.find("\rverifying ["), std::string::npos) << forced.output;
  EXPECT_NE(forced.output.find("\r\033[K"), std::string::npos) << "progress line not cleared";
  EXPECT_EQ(svc("verify --progress --no-progress " + quoted(file())).exit_code, 2);
}

// decode and verify take --threads; the bytes do not depend on it.
TEST_F(CliConventions, ThreadsChangeNothingButSpeed) {
  ASSERT_EQ(svc("decode --quiet --threads 1 " + quoted(file()) + " -o " + quoted(work("one"))).exit_code, 0);
  ASSERT_EQ(svc("decode --quiet --threads 4 " + quoted(file()) + " -o " + quoted(work("four"))).exit_code, 0);
  EXPECT_EQ(testing::expect_identical_trees(work("one"), work("four")), 9 * 6 + 2);
  // No staging folder is left beside the output.
  for (const auto& entry : fs::directory_iterator(dir_->path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
  // A damaged file: the same report for any thread count.
  std::string bytes = testing::read_file_bytes(file());
  bytes[bytes.size() / 2] ^= 0x5a;
  std::ofstream(work("damaged.svc"), std::ios::binary) << bytes;
  const CliRun one = svc("verify --threads 1 " + quoted(work("damaged.svc")));
  const CliRun four = svc("verify --threads 4 " + quoted(work("damaged.svc")));
  EXPECT_EQ(one.exit_code, 3) << one.output;
  EXPECT_EQ(four.exit_code, 3);
  EXPECT_EQ(one.output.substr(0, one.output.rfind('(')), four.output.substr(0, four.output.rfind('(')));
}

// encode --psnr reports what the library's metrics give on the decoded faces.
TEST_F(CliConventions, EncodePsnrMatchesTheMetrics) {
  const CliRun run = svc("encode --psnr --json -y " + quoted(db()) + " -o " + quoted(work("p.svc")));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json quality = parse_json(run)["quality"];
  auto manifest = load_manifest(db());
  auto reader = Reader::open(work("p.svc"));
  ASSERT_TRUE(manifest.ok() && reader.ok());
  SquaredError luma, rgb;
  double ssim = 0;
  for (size_t c = 0; c < manifest->cells.size(); ++c) {
    for (Face face : kAllFaces) {
      auto source = load_face(*manifest, c, face);
      auto decoded = (*reader)->decode_face(manifest->cells[c].index, face);
      ASSERT_TRUE(source.ok() && decoded.ok());
      luma.add(*luma_squared_error(source->color, *decoded));
      rgb.add(*rgb_squared_error(source->color, *decoded));
      ssim += *luma_ssim(source->color, *decoded);
    }
  }
  EXPECT_EQ(quality["faces"], 54);
  EXPECT_NEAR(quality["psnr_y"].get<double>(), luma.psnr(), 1e-9);
  EXPECT_NEAR(quality["psnr_rgb"].get<double>(), rgb.psnr(), 1e-9);
  EXPECT_NEAR(quality["ssim"].get<double>(), ssim / 54, 1e-9);
  const CliRun text = svc("encode --psnr -y " + quoted(db()) + " -o " + quoted(work("p.svc")));
  EXPECT_NE(text.output.find("PSNR-Y"), std::string::npos) << text.output;
}

// check validates without encoding, with the encoder's own errors.
TEST_F(CliConventions, CheckReportsWhatTheEncoderWouldRefuse) {
  const CliRun good = svc("check " + quoted(db()));
  EXPECT_EQ(good.exit_code, 0) << good.output;
  EXPECT_NE(good.output.find("9 cells"), std::string::npos) << good.output;

  const fs::path bad = copy_of_db("bad-size");
  const fs::path png = bad / "cells" / "1_0_1" / "nz.png";
  {
    std::vector<uint8_t> pixels(8 * 8 * 3, 100);
    auto out = OIIO::ImageOutput::create(png.string());
    ASSERT_TRUE(out && out->open(png.string(), OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
  }
  const CliRun check = svc("check " + quoted(bad));
  const CliRun encode = svc("encode " + quoted(bad) + " -o " + quoted(work("bad.svc")));
  EXPECT_EQ(check.exit_code, 1) << check.output;
  EXPECT_EQ(encode.exit_code, 1) << encode.output;
  const std::string error = encode.output.substr(0, encode.output.find('\n'));
  EXPECT_NE(error.find("cell (1,0,1), face nz"), std::string::npos) << error;
  EXPECT_NE(check.output.find(error), std::string::npos) << check.output;
  EXPECT_FALSE(fs::exists(work("bad.svc")));
}

// check reports every missing file, not the first alone, and still fails.
TEST_F(CliConventions, CheckReportsEveryMissingFile) {
  const fs::path bad = copy_of_db("two-missing");
  fs::remove(bad / "cells" / "0_0_0" / "px.png");
  fs::remove(bad / "cells" / "2_0_2" / "nz.png");
  const CliRun check = svc("check " + quoted(bad));
  EXPECT_EQ(check.exit_code, 1) << check.output;
  const size_t first = check.output.find("cell (0,0,0), face px");
  const size_t second = check.output.find("cell (2,0,2), face nz");
  EXPECT_NE(first, std::string::npos) << check.output;
  EXPECT_NE(second, std::string::npos) << check.output;
  EXPECT_LT(first, second) << check.output;
  EXPECT_NE(check.output.find("faces     52 of 54 listed load"), std::string::npos) << check.output;
  const CliRun json_run = svc("check --json " + quoted(bad));
  EXPECT_EQ(json_run.exit_code, 1);
  const json report = parse_json_after_errors(json_run);
  EXPECT_EQ(report["ok"], false);
  ASSERT_EQ(report["problems"].size(), 2u) << report.dump(2);
  EXPECT_NE(report["problems"][0].get<std::string>().find("px.png"), std::string::npos) << report.dump(2);
  EXPECT_NE(report["problems"][1].get<std::string>().find("nz.png"), std::string::npos) << report.dump(2);
}

// decode --face writes a database of those faces that check accepts (saying that the
// encoder needs whole cubes); decode of whole cells writes one that encodes again.
TEST_F(CliConventions, DecodedFacesMakeADatabaseCheckAccepts) {
  const fs::path one = work("one-face");
  ASSERT_EQ(svc("decode --quiet " + quoted(file()) + " --cell 1,0,1 --face pz -o " + quoted(one)).exit_code, 0);
  const json manifest = json::parse(testing::read_file_bytes(one / "manifest.json"));
  ASSERT_EQ(manifest["cells"].size(), 1u) << manifest.dump(2);
  EXPECT_EQ(manifest["cells"][0]["index"], json::array({1, 0, 1}));
  EXPECT_EQ(manifest["cells"][0]["faces"].size(), 1u);
  EXPECT_TRUE(manifest["cells"][0]["faces"].contains("pz"));
  const CliRun check = svc("check --json " + quoted(one));
  EXPECT_EQ(check.exit_code, 0) << check.output;
  const json report = parse_json(check);
  EXPECT_EQ(report["ok"], true);
  EXPECT_EQ(report["encodable"], false);
  EXPECT_EQ(report["cells"], 1);
  EXPECT_EQ(report["partial_cells"], 1);
  EXPECT_EQ(report["faces"], 1);
  EXPECT_EQ(report["problems"].size(), 0u);
  const CliRun summary = svc("check " + quoted(one));
  EXPECT_NE(summary.output.find("svc encode needs all six faces of a cell"), std::string::npos) << summary.output;
  const CliRun encode = svc("encode " + quoted(one) + " -o " + quoted(work("one-face.svc")));
  EXPECT_EQ(encode.exit_code, 1) << encode.output;
  EXPECT_NE(encode.output.find("missing face \"px\""), std::string::npos) << encode.output;

  const fs::path cube = work("one-cell");
  ASSERT_EQ(svc("decode --quiet " + quoted(file()) + " --cell 1,0,1 -o " + quoted(cube)).exit_code, 0);
  const json whole = parse_json(svc("check --json " + quoted(cube)));
  EXPECT_EQ(whole["encodable"], true) << whole.dump(2);
  EXPECT_EQ(whole["faces"], 6);
  EXPECT_EQ(svc("encode --quiet " + quoted(cube) + " -o " + quoted(work("one-cell.svc"))).exit_code, 0);
}

// verify names the damaged chunk first, before the faces that need it; --json lists
// every problem; a file too short to open still gives JSON.
TEST_F(CliConventions, VerifyNamesTheDamagedChunkFirst) {
  auto reader = Reader::open(file());
  ASSERT_TRUE(reader.ok());
  const auto& cells = (*reader)->cells();
  // An I-face that a B-face earlier in the file needs.
  std::optional<std::pair<size_t, Face>> target;
  for (size_t c = 0; c < cells.size() && !target; ++c) {
    for (Face face : kAllFaces) {
      for (const auto& [ref_cell, ref_face] : cells[c].faces[static_cast<int>(face)].references) {
        if (ref_cell * kFaceCount + static_cast<size_t>(ref_face) > c * kFaceCount + static_cast<size_t>(face)) {
          target.emplace(ref_cell, ref_face);
        }
      }
      if (target) break;
    }
  }
  ASSERT_TRUE(target) << "no B-face comes before one of its references";
  const FaceEntry& entry = cells[target->first].faces[static_cast<int>(target->second)];
  std::string bytes = testing::read_file_bytes(file());
  bytes[entry.offset + entry.coded_bytes / 2 + 8] ^= 0x5a;
  std::ofstream(work("chunk-damaged.svc"), std::ios::binary) << bytes;
  const std::string damaged = face_label(cells[target->first].index, target->second);

  const CliRun text = svc("verify " + quoted(work("chunk-damaged.svc")));
  EXPECT_EQ(text.exit_code, 3) << text.output;
  const size_t header = text.output.find("is damaged:\n");
  ASSERT_NE(header, std::string::npos) << text.output;
  const std::string first_line = text.output.substr(header + 12, text.output.find('\n', header + 12) - header - 12);
  EXPECT_NE(first_line.find(damaged), std::string::npos) << text.output;
  EXPECT_EQ(first_line.find("cannot be decoded: its reference"), std::string::npos) << text.output;

  const CliRun json_run = svc("verify --json " + quoted(work("chunk-damaged.svc")));
  EXPECT_EQ(json_run.exit_code, 3);
  const json report = parse_json_after_errors(json_run);
  EXPECT_EQ(report["ok"], false);
  ASSERT_TRUE(report["problems"].is_array());
  ASSERT_GE(report["problems"].size(), 2u) << report.dump(2);
  EXPECT_EQ(report["problems"][0], first_line);
  for (size_t i = 1; i < report["problems"].size(); ++i) {
    EXPECT_NE(report["problems"][i].get<std::string>().find("cannot be decoded: its reference"), std::string::npos)
        << report["problems"][i];
  }

  std::ofstream(work("truncated.svc"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const CliRun truncated = svc("verify --json " + quoted(work("truncated.svc")));
  EXPECT_NE(truncated.exit_code, 0);
  const json short_report = parse_json_after_errors(truncated);
  EXPECT_EQ(short_report["command"], "verify");
  EXPECT_EQ(short_report["ok"], false);
  ASSERT_EQ(short_report["problems"].size(), 1u) << short_report.dump(2);
  EXPECT_FALSE(short_report["problems"][0].get<std::string>().empty());
}

// A damaged PNG is reported by svc alone: one line, no image library chatter.
TEST_F(CliConventions, DamagedImagesGiveOnlySvcsMessage) {
  const fs::path broken = copy_of_db("broken-png");
  const fs::path png = broken / "cells" / "0_0_0" / "py.png";
  const std::string bytes = testing::read_file_bytes(png);
  std::ofstream(png, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() - 30);
  for (const std::string& command : {std::string("encode ") + quoted(broken) + " -o " + quoted(work("broken.svc")),
                                     std::string("check ") + quoted(broken)}) {
    const CliRun run = svc(command);
    EXPECT_EQ(run.exit_code, 1) << run.output;
    const std::string first = run.output.substr(0, run.output.find('\n'));
    EXPECT_NE(first.find("cell (0,0,0), face py"), std::string::npos) << run.output;
    EXPECT_NE(first.find("damaged PNG"), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("libpng"), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("PNG library"), std::string::npos) << run.output;
    if (command.rfind("encode", 0) == 0) EXPECT_EQ(run.output, first + "\n");
  }
}

// A manifest may not pull in files from outside its folder unless the user allows it.
TEST_F(CliConventions, OutsidePathsNeedTheFlag) {
  const fs::path db2 = copy_of_db("outside");
  const fs::path secret = work("secret.png");
  fs::copy_file(db2 / "cells" / "0_0_0" / "px.png", secret);
  json manifest = json::parse(testing::read_file_bytes(db2 / "manifest.json"));
  manifest["cells"][0]["faces"]["px"]["color"] = "../secret.png";
  std::ofstream(db2 / "manifest.json", std::ios::trunc) << manifest.dump(2);
  for (const std::string& command : {std::string("encode ") + quoted(db2) + " -o " + quoted(work("outside.svc")),
                                     std::string("check ") + quoted(db2)}) {
    const CliRun refused = svc(command);
    EXPECT_EQ(refused.exit_code, 1) << refused.output;
    EXPECT_NE(refused.output.find("../secret.png\" lies outside the database folder"), std::string::npos)
        << refused.output;
    EXPECT_EQ(svc(command + " --allow-outside-paths").exit_code, 0);
  }
}

TEST_F(CliConventions, EncodeOfAnSvcFileSaysWhatItExpected) {
  const CliRun run = svc("encode " + quoted(file()) + " -o " + quoted(work("again.svc")));
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("encode expects a database folder"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(work("again.svc")));
}

TEST_F(CliConventions, BenchNamesTheValidCodecsAndLeavesNothingOnFailure) {
  if (svc("bench --help").exit_code != 0) GTEST_SKIP() << "svc built without the benchmark";
  const CliRun unknown = svc("bench " + quoted(db()) + " --codecs svc,foo --out " + quoted(work("bench-foo")));
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("'foo' (valid: svc, svc-regular, svc-intra, svc-fast, svc-fastest, mpeg2"),
            std::string::npos)
      << unknown.output;
  for (const char* option : {"avif", "avif=aom-params", "=aom-params=x", "avif==1"}) {
    const CliRun malformed =
        svc("bench " + quoted(db()) + " --anchor-option " + option + " --out " + quoted(work("bench-option")));
    EXPECT_EQ(malformed.exit_code, 2) << malformed.output;
    EXPECT_NE(malformed.output.find("--anchor-option wants CODEC=KEY=VALUE"), std::string::npos)
        << malformed.output;
    EXPECT_FALSE(fs::exists(work("bench-option")));
  }
  const CliRun missing = svc("bench nope --out " + quoted(work("bench-nope")));
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_FALSE(fs::exists(work("bench-nope"))) << missing.output;
  EXPECT_FALSE(fs::exists(work("bench-foo")));
}

// The legend names every macroblock mode, and warped prediction, in its own color; the
// sheet is readable.
TEST_F(CliConventions, InspectDrawsALegendAtAReadableScale) {
  const fs::path png = work("legend.png");
  ASSERT_EQ(svc("inspect -y " + quoted(file()) + " --cell 1,0,0 --face px -o " + quoted(png)).exit_code, 0);
  auto in = OIIO::ImageInput::open(png.string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec spec = in->spec();
  EXPECT_GE(spec.height, 512);
  std::vector<uint8_t> pixels(static_cast<size_t>(spec.width) * spec.height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
  // Each mode's pure color fills its legend swatch.
  const std::vector<std::array<uint8_t, 3>> colors = {{220, 40, 40},  {40, 190, 60},  {240, 200, 30},
                                                      {170, 60, 220}, {40, 110, 240}, {30, 200, 200}};
  for (const auto& color : colors) {
    size_t count = 0;
    for (size_t p = 0; p < pixels.size(); p += 3) {
      count += pixels[p] == color[0] && pixels[p + 1] == color[1] && pixels[p + 2] == color[2];
    }
    EXPECT_GE(count, 36u) << int(color[0]) << "," << int(color[1]) << "," << int(color[2]);
  }
}

// svc-scene writes into a staging folder: -y replaces what it writes whole (no old
// image survives beside the new ones; the user's other files stay), and --json reports
// what was written.
TEST_F(CliConventions, SceneReplacesWhatItWritesAndReportsJson) {
  const fs::path out = work("scene-json");
  fs::create_directories(out / "cells" / "9_9_9");
  std::ofstream(out / "cells" / "9_9_9" / "px.png") << "old";
  std::ofstream(out / "notes.txt") << "mine";
  const CliRun refused = run_program("svc-scene", quoted(out) + " --grid 2,1,1 --face-size 16", dir_->path());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("svc-scene: will not write"), std::string::npos) << refused.output;
  const CliRun run = run_program("svc-scene", quoted(out) + " -y --json --grid 2,1,1 --face-size 16", dir_->path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json result = parse_json(run);
  EXPECT_EQ(result["command"], "svc-scene");
  EXPECT_EQ(result["output"], out.string());
  EXPECT_EQ(result["cells"], 2);
  EXPECT_EQ(result["faces"], 12);
  EXPECT_EQ(result["grid"]["dims"], json::array({2, 1, 1}));
  EXPECT_FALSE(fs::exists(out / "cells" / "9_9_9")) << "old content mixed into the new database";
  EXPECT_TRUE(fs::exists(out / "cells" / "1_0_0" / "nz.exr"));
  EXPECT_EQ(testing::read_file_bytes(out / "notes.txt"), "mine");
  const json manifest = json::parse(testing::read_file_bytes(out / "manifest.json"));
  EXPECT_EQ(manifest["cells"].size(), 2u);
  expect_no_staging_left(dir_->path(), ".scene-json");
}

// decode -y replaces what it writes whole: a decode of one cell over a full one leaves
// one cell, not a mix; the folder holding the .svc file being read is refused even with -y.
TEST_F(CliConventions, DecodeReplacesWhatItWrites) {
  const fs::path out = work("decode-replaced");
  ASSERT_EQ(svc("decode --quiet " + quoted(file()) + " -o " + quoted(out)).exit_code, 0);
  const CliRun refused = svc("decode --quiet --cell 1,0,1 " + quoted(file()) + " -o " + quoted(out));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("-y to replace it"), std::string::npos) << refused.output;
  const CliRun replaced = svc("decode --quiet -y --cell 1,0,1 " + quoted(file()) + " -o " + quoted(out));
  ASSERT_EQ(replaced.exit_code, 0) << replaced.output;
  std::vector<std::string> cells;
  for (const auto& entry : fs::directory_iterator(out / "cells")) cells.push_back(entry.path().filename());
  EXPECT_EQ(cells, std::vector<std::string>{"1_0_1"});
  const json manifest = json::parse(testing::read_file_bytes(out / "manifest.json"));
  EXPECT_EQ(manifest["cells"].size(), 1u);
  expect_no_staging_left(dir_->path(), ".decode-replaced");
  // "-o ." names the current folder: staged beside it, not inside it.
  const fs::path here = work("decode-here");
  fs::create_directories(here);
  std::ofstream(here / "notes.txt") << "mine";
  ASSERT_EQ(run_program("svc", "decode --quiet -y " + quoted(file()) + " -o .", here).exit_code, 0);
  EXPECT_TRUE(fs::exists(here / "cells" / "1_0_1" / "pz.png"));
  EXPECT_EQ(testing::read_file_bytes(here / "notes.txt"), "mine");
  std::vector<std::string> entries;
  for (const auto& entry : fs::directory_iterator(here)) entries.push_back(entry.path().filename());
  std::sort(entries.begin(), entries.end());
  EXPECT_EQ(entries, (std::vector<std::string>{"cells", "depth-unknown.exr", "manifest.json", "notes.txt"}));
  const CliRun own_folder = svc("decode -y " + quoted(file()) + " -o " + quoted(dir_->path()));
  EXPECT_EQ(own_folder.exit_code, 2) << own_folder.output;
  EXPECT_NE(own_folder.output.find("it holds the input"), std::string::npos) << own_folder.output;
  EXPECT_TRUE(fs::exists(file()));
}

// svc-walkthrough follows the same conventions: "svc-walkthrough: " on every message,
// exit 2 for a usage error, 3 for a damaged file.
TEST_F(CliConventions, WalkthroughExitCodesAndMessages) {
  const CliRun usage = run_program("svc-walkthrough", "--bogus " + quoted(file()), dir_->path());
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
  EXPECT_EQ(usage.output.rfind("svc-walkthrough: ", 0), 0u) << usage.output;
  const fs::path damaged = work("damaged-walk.svc");
  std::string bytes = testing::read_file_bytes(file());
  bytes.resize(bytes.size() / 2);
  std::ofstream(damaged, std::ios::binary) << bytes;
  const CliRun corrupt = run_program("svc-walkthrough", quoted(damaged), dir_->path());
  EXPECT_EQ(corrupt.exit_code, 3) << corrupt.output;
  EXPECT_EQ(corrupt.output.rfind("svc-walkthrough: ", 0), 0u) << corrupt.output;
  const CliRun ok =
      run_program("svc-walkthrough", "--json --steps 3 --no-prefetch " + quoted(file()), dir_->path());
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const json result = parse_json(ok);
  EXPECT_EQ(result["command"], "svc-walkthrough");
  EXPECT_EQ(result["input"], file().string());
  EXPECT_EQ(result["runs"][0]["steps"], 3);
  EXPECT_NE(run_program("svc-walkthrough", "--help", dir_->path()).output.find("3 damaged .svc file"),
            std::string::npos);
}

// demo --json uses encode's names for what it encoded and adds what it decoded; with
// --keep the figures describe the files kept.
TEST_F(CliConventions, DemoReportsJsonInEncodesNames) {
  const fs::path kept = work("demo-kept");
  const CliRun run = svc("demo --json --grid 2,1,2 --face-size 32 --threads 2 --keep " + quoted(kept));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json result = parse_json(run);
  EXPECT_EQ(result["command"], "demo");
  EXPECT_EQ(result["cells"], 4);
  EXPECT_EQ(result["faces"], 24);
  EXPECT_EQ(result["output"], (kept / "scene.svc").string());
  EXPECT_EQ(result["file_bytes"].get<uint64_t>(), fs::file_size(kept / "scene.svc"));
  const CliRun info = svc("info --json " + quoted(kept / "scene.svc"));
  const json i = parse_json(info);
  for (const char* type : {"intra", "predicted"}) EXPECT_EQ(result["face_types"][type], i["face_types"][type]);
  EXPECT_EQ(result["quality"]["faces"].get<uint64_t>(), 6 * result["decoded_cells"].size());
  EXPECT_GT(result["quality"]["psnr_y"].get<double>(), 20.0);
  expect_no_staging_left(dir_->path(), ".demo-kept");
}

// bench --json prints the command, input and output as the other commands name them and
// the results.json it wrote; --quiet prints nothing.
TEST_F(CliConventions, BenchReportsJson) {
  if (svc("bench --help").exit_code != 0) GTEST_SKIP() << "svc built without the benchmark";
  const fs::path out = work("bench-json");
  const std::string args = "bench " + quoted(db()) + " --codecs jpeg --quick --no-experiments --threads 2 --out ";
  const CliRun run = svc(args + quoted(out) + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json result = parse_json(run);
  EXPECT_EQ(result["command"], "bench");
  EXPECT_EQ(result["input"], db().string());
  EXPECT_EQ(result["output"], out.string());
  EXPECT_EQ(result["results"], json::parse(testing::read_file_bytes(out / "results.json")));
  EXPECT_EQ(result["results"]["database"]["faces"], 54);
  EXPECT_EQ(svc(args + quoted(work("bench-quiet")) + " --quiet").output, "");
  EXPECT_TRUE(fs::exists(work("bench-quiet") / "results.json"));
}

// --- Interrupts -------------------------------------------------------------------

struct Spawned {
  pid_t pid = -1;
  fs::path log;
};

// Starts build/bin/PROGRAM ARGS with stdout and stderr into `log`.
Spawned spawn_program(const std::string& name, const std::vector<std::string>& args, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  const std::string program = (fs::path(SVC_BINARY_DIR) / "bin" / name).string();
  std::vector<char*> argv{const_cast<char*>(program.c_str())};
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  Spawned spawned{-1, log};
  if (posix_spawn(&spawned.pid, program.c_str(), &actions, nullptr, argv.data(), environ) != 0) spawned.pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return spawned;
}

Spawned spawn_svc(const std::vector<std::string>& args, const fs::path& log) {
  return spawn_program("svc", args, log);
}

// Waits until the log shows `text` (the work has started), then sends `signal`; returns
// the exit status, or -1 when the program was not stopped by the signal's request.
int interrupt_when(const Spawned& spawned, const std::string& text, int signal) {
  for (int i = 0; i < 2000 && testing::read_file_bytes(spawned.log).find(text) == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(spawned.pid, signal);
  int status = 0;
  ::waitpid(spawned.pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class CliInterrupts : public CliConventions {
 protected:
  static void SetUpTestSuite() {
    CliConventions::SetUpTestSuite();
    samples::SceneOptions options;
    options.grid = {8, 1, 8};
    options.face_size = 96;
    options.threads = 2;
    ASSERT_TRUE(samples::generate_scene(options, big_db()).ok());
  }
  static fs::path big_db() { return dir_->path() / "big"; }

  static void expect_nothing_left(const fs::path& folder, const std::string& stem) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      EXPECT_EQ(entry.path().filename().string().find(stem), std::string::npos) << entry.path() << " left behind";
    }
  }
};

// SIGINT and SIGTERM stop an encode: exit 130 / 143, no output, no temporary, the
// progress line cleared.
TEST_F(CliInterrupts, EncodeLeavesNothing) {
  const std::vector<std::pair<int, int>> signals = {{SIGINT, 130}, {SIGTERM, 143}};
  for (const auto& [signal, code] : signals) {
    const fs::path out = work("stopped.svc");
    const Spawned run = spawn_svc({"encode", "--progress", "--threads", "1", big_db().string(), "-o", out.string()},
                                  work("encode.log"));
    ASSERT_GT(run.pid, 0);
    EXPECT_EQ(interrupt_when(run, "encoding [", signal), code) << testing::read_file_bytes(run.log);
    const std::string log = testing::read_file_bytes(run.log);
    EXPECT_NE(log.find("\r\033[Ksvc: stopped by SIG"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(out));
    expect_nothing_left(dir_->path(), "stopped.svc");
  }
  EXPECT_NE(svc("--help").output.find("130 or 143 stopped by SIGINT"), std::string::npos);
}

TEST_F(CliInterrupts, DecodeLeavesNothing) {
  ASSERT_EQ(svc("encode --quiet " + quoted(big_db()) + " -o " + quoted(work("big.svc"))).exit_code, 0);
  const fs::path out = work("stopped-decode");
  const Spawned run =
      spawn_svc({"decode", "--progress", "--threads", "1", work("big.svc").string(), "-o", out.string()},
                work("decode.log"));
  ASSERT_GT(run.pid, 0);
  EXPECT_EQ(interrupt_when(run, "decoding [", SIGINT), 130) << testing::read_file_bytes(run.log);
  EXPECT_FALSE(fs::exists(out));
  expect_nothing_left(dir_->path(), "stopped-decode");
}

// An interrupted add leaves the file as it was.
TEST_F(CliInterrupts, AddLeavesTheFileAsItWas) {
  const fs::path part = work("part");
  samples::SceneOptions options;
  options.grid = {8, 1, 2};
  options.face_size = 96;
  options.origin = samples::scene_grid_origin([] {
    samples::SceneOptions o;
    o.grid = {8, 1, 8};
    return o;
  }());
  options.threads = 2;
  ASSERT_TRUE(samples::generate_scene(options, part).ok());
  const fs::path target = work("add-target.svc");
  ASSERT_EQ(svc("encode --quiet " + quoted(part) + " -o " + quoted(target)).exit_code, 0);
  const std::string before = testing::read_file_bytes(target);
  const Spawned run =
      spawn_svc({"add", "--progress", "--threads", "1", target.string(), big_db().string()}, work("add.log"));
  ASSERT_GT(run.pid, 0);
  EXPECT_EQ(interrupt_when(run, "adding [", SIGTERM), 143) << testing::read_file_bytes(run.log);
  auto reader = Reader::open(target);
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  EXPECT_EQ((*reader)->cells().size(), 16u);
  EXPECT_TRUE((*reader)->verify().ok());
}

// An interrupted benchmark removes its work folder, and the output folder it created.
TEST_F(CliInterrupts, BenchLeavesNothing) {
  if (svc("bench --help").exit_code != 0) GTEST_SKIP() << "svc built without the benchmark";
  const fs::path out = work("stopped-bench");
  const Spawned run = spawn_svc({"bench", big_db().string(), "--codecs", "svc,jpeg", "--quick", "--no-experiments",
                                 "--threads", "1", "--out", out.string()},
                                work("bench.log"));
  ASSERT_GT(run.pid, 0);
  EXPECT_EQ(interrupt_when(run, "quality search", SIGINT), 130) << testing::read_file_bytes(run.log);
  EXPECT_FALSE(fs::exists(out)) << testing::read_file_bytes(run.log);
}

// An interrupted svc-scene leaves no half-written database, and no staging folder.
TEST_F(CliInterrupts, SceneLeavesNothing) {
  const std::vector<std::pair<int, int>> signals = {{SIGINT, 130}, {SIGTERM, 143}};
  for (const auto& [signal, code] : signals) {
    const fs::path out = work("stopped-scene");
    const Spawned run =
        spawn_program("svc-scene",
                      {out.string(), "--grid", "8,1,8", "--face-size", "96", "--threads", "1", "--progress"},
                      work("scene.log"));
    ASSERT_GT(run.pid, 0);
    EXPECT_EQ(interrupt_when(run, "generating [", signal), code) << testing::read_file_bytes(run.log);
    const std::string log = testing::read_file_bytes(run.log);
    EXPECT_NE(log.find("\r\033[Ksvc-scene: stopped by SIG"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(out));
    expect_nothing_left(dir_->path(), "stopped-scene");
  }
}

// An interrupted decode -y into an existing database leaves that database as it was.
TEST_F(CliInterrupts, DecodeOverAnExistingFolderKeepsItOnInterrupt) {
  ASSERT_EQ(svc("encode --quiet -y " + quoted(big_db()) + " -o " + quoted(work("big-y.svc"))).exit_code, 0);
  const fs::path out = work("kept-decode");
  ASSERT_EQ(svc("decode --quiet " + quoted(file()) + " -o " + quoted(out)).exit_code, 0);
  const std::string manifest = testing::read_file_bytes(out / "manifest.json");
  const Spawned run =
      spawn_svc({"decode", "-y", "--progress", "--threads", "1", work("big-y.svc").string(), "-o", out.string()},
                work("decode-y.log"));
  ASSERT_GT(run.pid, 0);
  EXPECT_EQ(interrupt_when(run, "decoding [", SIGTERM), 143) << testing::read_file_bytes(run.log);
  EXPECT_EQ(testing::read_file_bytes(out / "manifest.json"), manifest);
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "cells"), fs::directory_iterator()), 9);
  expect_nothing_left(dir_->path(), ".kept-decode");
}

}  // namespace
}  // namespace svc
