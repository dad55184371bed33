// SPDX-License-Identifier: BSD-2-Clause
// `svc bench` end to end on a tiny scene with fast codecs: results.json, results.csv,
// report.md and valid PNG plots, with numbers that agree with each other.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <tuple>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "bd_rate.h"
#include "rd_curve.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc_bench.h"

namespace svc::bench {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class BenchRun : public ::testing::Test {
 protected:
  static constexpr int kRandomAccesses = 12;  // random (cell, face) picks of the suite's run

  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-bench-run");
    samples::SceneOptions scene;
    scene.grid = {2, 1, 2};
    scene.face_size = 32;
    ASSERT_TRUE(samples::generate_scene(scene, dir_->path() / "db").ok());
    BenchOptions options;
    options.db_dir = dir_->path() / "db";
    options.out_dir = dir_->path() / "out";
    options.codecs = {"png", "svc", "mpeg2", "jpeg"};  // run in report order whatever the order here
    options.quick = true;
    options.ablation = true;
    options.random_accesses = kRandomAccesses;
    options.threads = 2;
    options.progress = [](const std::string& line) { progress_lines_.push_back(line); };
    auto results = run_bench(options);
    ASSERT_TRUE(results.ok()) << results.status().to_string();
    results_ = new BenchResults(std::move(results).value());
    ASSERT_TRUE(write_all(*results_, options.out_dir).ok());
  }
  static void TearDownTestSuite() {
    delete results_;
    delete dir_;
  }
  static fs::path out() { return dir_->path() / "out"; }

  static testing::TempDir* dir_;
  static BenchResults* results_;
  static std::vector<std::string> progress_lines_;
};

testing::TempDir* BenchRun::dir_ = nullptr;
BenchResults* BenchRun::results_ = nullptr;
std::vector<std::string> BenchRun::progress_lines_;

TEST_F(BenchRun, ResultsJsonHasEveryCodecWithConsistentNumbers) {
  ASSERT_TRUE(results_);
  const auto j = nlohmann::json::parse(read_text(out() / "results.json"));
  EXPECT_EQ(j["database"]["cells"], 4);
  EXPECT_EQ(j["database"]["faces"], 24);
  const uint64_t raw = 24ull * 32 * 32 * 3;
  EXPECT_EQ(j["database"]["raw_bytes"], raw);
  ASSERT_EQ(j["codecs"].size(), 4u);
  const std::vector<std::string> order = {"svc", "mpeg2", "jpeg", "png"};
  for (size_t i = 0; i < order.size(); ++i) {
    const auto& c = j["codecs"][i];
    EXPECT_EQ(c["name"], order[i]);
    EXPECT_FALSE(c["skipped"].get<bool>());
    ASSERT_GE(c["points"].size(), 1u);
    for (const auto& p : c["points"]) {
      const uint64_t bytes = p["bytes"];
      EXPECT_GT(bytes, 0u);
      EXPECT_NEAR(p["compression_ratio"].get<double>(), double(raw) / bytes, 1e-6);
      EXPECT_NEAR(p["bits_per_pixel"].get<double>(), 8.0 * bytes / (24.0 * 32 * 32), 1e-9);
      EXPECT_GT(p["psnr_y"].get<double>(), 20.0);
      EXPECT_GT(p["psnr_rgb"].get<double>(), 20.0);
      EXPECT_GT(p["ssim"].get<double>(), 0.5);
      EXPECT_LE(p["ssim"].get<double>(), 1.0);
    }
    const int ref = c["reference_point"];
    ASSERT_GE(ref, 0);
    ASSERT_LT(ref, static_cast<int>(c["points"].size()));
    EXPECT_GT(c["speed"]["encode_faces_per_second"].get<double>(), 0);
    EXPECT_GT(c["speed"]["decode_faces_per_second"].get<double>(), 0);
    EXPECT_GT(c["speed"]["decode_faces_per_second_all_threads"].get<double>(), 0);
    for (const char* mode : {"cold", "warm"}) {
      // One sample per picked cell in each of the kDecodeSpeedPasses rounds.
      const auto& a = c["random_cell_access"][mode];
      EXPECT_GE(a["samples"].get<int>(), kDecodeSpeedPasses);
      EXPECT_LE(a["samples"].get<int>(), kRandomAccesses * kDecodeSpeedPasses);
      EXPECT_EQ(a["samples"].get<int>() % kDecodeSpeedPasses, 0);
      EXPECT_GE(a["mean_frames_decoded"].get<double>(), 6.0);  // a cell is six faces
      EXPECT_GT(a["mean_ms"].get<double>(), 0);
    }
    for (const char* mode : {"cold", "warm"}) {
      const auto& a = c["random_access"][mode];
      EXPECT_EQ(a["samples"], kRandomAccesses);
      EXPECT_GE(a["mean_frames_decoded"].get<double>(), 1.0);
      EXPECT_GT(a["mean_ms"].get<double>(), 0);
      EXPECT_GE(a["p99_ms"].get<double>(), a["mean_ms"].get<double>() * 0.999);
    }
  }
  // png is lossless and decodes one frame per face; jpeg is intra too.
  EXPECT_EQ(j["codecs"][3]["points"][0]["psnr_y"], 99.0);
  EXPECT_EQ(j["codecs"][3]["random_access"]["cold"]["max_frames_decoded"], 1);
  EXPECT_EQ(j["codecs"][2]["random_access"]["warm"]["mean_frames_decoded"], 1.0);
  // svc: a face, at most two reference faces and, with cube references, at most the
  // four adjacent faces of each reference cube.
  EXPECT_LE(j["codecs"][0]["random_access"]["cold"]["max_frames_decoded"].get<int>(), 11);
  // A cell: its six faces and at most its two reference cubes.
  EXPECT_LE(j["codecs"][0]["random_cell_access"]["cold"]["max_frames_decoded"].get<int>(), 18);
  EXPECT_EQ(j["codecs"][3]["random_cell_access"]["cold"]["max_frames_decoded"], 6);
  // MPEG-2 row-major: an I-frame starts every row of 2 cells, so at most I, I, B.
  EXPECT_LE(j["codecs"][1]["random_access"]["cold"]["max_frames_decoded"].get<int>(), 3);
}

TEST_F(BenchRun, BdRateMatchesTheCurvesInTheResults) {
  ASSERT_TRUE(results_);
  const CodecResult* svc = nullptr;
  for (const CodecResult& c : results_->codecs) {
    if (c.name == "svc") svc = &c;
  }
  ASSERT_TRUE(svc);
  auto curve = [](const CodecResult& c) {
    std::vector<RdPoint> rd;
    for (const QualityPoint& p : c.points) rd.push_back({p.setting, double(p.bytes), p.psnr_y, 0});
    return RdCurve(rd);
  };
  for (const CodecResult& c : results_->codecs) {
    if (&c == svc) continue;
    const auto expected = bd_rate_ratio(curve(c), curve(*svc));
    if (c.points.size() < 2 || !expected) {
      EXPECT_FALSE(c.bd_rate_svc.has_value()) << c.name;
      continue;
    }
    ASSERT_TRUE(c.bd_rate_svc.has_value()) << c.name;
    EXPECT_NEAR(*c.bd_rate_svc, *expected - 1, 1e-12) << c.name;
    EXPECT_EQ(results_->bd_reference, "svc");
    // The same on PSNR-RGB, with the overlap it was averaged over.
    auto rgb_points = [](const CodecResult& r) {
      std::vector<RatePoint> points;
      for (const QualityPoint& p : r.points) points.push_back({double(p.bytes), p.psnr_rgb});
      return points;
    };
    const auto rgb = bd_rate(rgb_points(c), rgb_points(*svc));
    ASSERT_EQ(rgb.has_value(), c.bd_rate_svc_rgb.has_value()) << c.name;
    if (!rgb) continue;
    EXPECT_NEAR(*c.bd_rate_svc_rgb, rgb->ratio - 1, 1e-12) << c.name;
    EXPECT_DOUBLE_EQ(c.bd_range_rgb[0], rgb->psnr_low) << c.name;
    EXPECT_DOUBLE_EQ(c.bd_range_rgb[1], rgb->psnr_high) << c.name;
  }
  const std::string report = read_text(out() / "report.md");
  EXPECT_LT(report.find("## Ranking by BD-rate"), report.find("## Summary at svc"));
}

// One row per coding tool and one with all of them off, each at svc's own settings,
// with the BD-rate its points give against svc's.
TEST_F(BenchRun, AblationEncodesWithoutEachTool) {
  ASSERT_TRUE(results_);
  const CodecResult* svc = nullptr;
  for (const CodecResult& c : results_->codecs) {
    if (c.name == "svc") svc = &c;
  }
  ASSERT_TRUE(svc);
  std::vector<std::string> expected = coding_tool_names();
  expected.push_back("all");
  ASSERT_EQ(results_->ablation.size(), expected.size());
  auto psnr_y = [](const std::vector<QualityPoint>& points) {
    std::vector<RatePoint> rate;
    for (const QualityPoint& p : points) rate.push_back({double(p.bytes), p.psnr_y});
    return rate;
  };
  const std::string report = read_text(out() / "report.md");
  for (size_t i = 0; i < expected.size(); ++i) {
    const AblationRow& row = results_->ablation[i];
    EXPECT_EQ(row.tool, expected[i]);
    ASSERT_EQ(row.points.size(), svc->points.size()) << row.tool;
    for (size_t k = 0; k < row.points.size(); ++k) {
      EXPECT_EQ(row.points[k].setting, svc->points[k].setting) << row.tool;
      EXPECT_GT(row.points[k].bytes, 0u) << row.tool;
    }
    const auto bd = bd_rate(psnr_y(svc->points), psnr_y(row.points));
    ASSERT_EQ(bd.has_value(), row.bd_rate_y.has_value()) << row.tool;
    if (bd) EXPECT_NEAR(*row.bd_rate_y, bd->ratio - 1, 1e-12) << row.tool;
    EXPECT_NE(report.find("| " + row.tool + " | "), std::string::npos) << row.tool;
  }
}

// svc's points record the B-faces apart; a second run against the first one's
// results.json finds the same encoder: BD-rate 0 on the whole database and the B-faces.
TEST_F(BenchRun, ComparesWithAnEarlierRunsSvc) {
  ASSERT_TRUE(results_);
  for (const CodecResult& c : results_->codecs) {
    if (c.name != "svc") continue;
    for (const QualityPoint& p : c.points) {
      EXPECT_GT(p.b_face_bytes, 0u);
      EXPECT_LT(p.b_face_bytes, p.bytes);
      EXPECT_GT(p.b_face_psnr_y, 20.0);
    }
  }
  BenchOptions options;
  options.db_dir = dir_->path() / "db";
  options.out_dir = dir_->path() / "again";
  options.codecs = {"svc"};
  options.quick = true;
  options.experiments = false;
  options.random_accesses = 4;
  options.threads = 2;
  options.before_results = out() / "results.json";
  auto again = run_bench(options);
  ASSERT_TRUE(again.ok()) << again.status().to_string();
  ASSERT_TRUE(again->before);
  ASSERT_TRUE(again->before->bd_rate_y && again->before->b_faces_bd_rate);
  EXPECT_NEAR(*again->before->bd_rate_y, 0.0, 1e-9);
  EXPECT_NEAR(*again->before->b_faces_bd_rate, 0.0, 1e-9);

  options.before_results = out() / "report.md";
  const auto refused = run_bench(options);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("report.md"), std::string::npos);
}

// svc-fast is svc at encoder speed 1 and svc-fastest at the highest: the same qualities,
// other bytes, the speed named in the report's description and measured like svc's.
TEST_F(BenchRun, SvcFastEncodesAtSpeedOne) {
  BenchOptions options;
  options.db_dir = dir_->path() / "db";
  options.out_dir = dir_->path() / "fast";
  options.codecs = {"svc-fastest", "svc-fast", "svc"};
  options.quick = true;
  options.experiments = false;
  options.random_accesses = 4;
  options.threads = 2;
  auto results = run_bench(options);
  ASSERT_TRUE(results.ok()) << results.status().to_string();
  ASSERT_EQ(results->codecs.size(), 3u);
  const CodecResult& svc = results->codecs[0];
  ASSERT_EQ(svc.name, "svc");
  EXPECT_EQ(results->bd_reference, "svc");
  for (const auto& [index, name, speed] : {std::tuple{1, "svc-fast", 1}, {2, "svc-fastest", kMaxEncoderSpeed}}) {
    const CodecResult& fast = results->codecs[static_cast<size_t>(index)];
    ASSERT_EQ(fast.name, name);
    EXPECT_NE(fast.description.find("encoder speed " + std::to_string(speed)), std::string::npos)
        << fast.description;
    const bool regular = speed_layout(speed) == CubeLayout::kRegular;
    EXPECT_EQ(fast.description.find("nearest references") != std::string::npos, regular) << fast.description;
    EXPECT_GT(fast.encode_faces_per_second, 0.0);
    EXPECT_GT(fast.decode_faces_per_second, 0.0);
    int compared = 0;
    for (const QualityPoint& a : svc.points) {
      for (const QualityPoint& b : fast.points) {
        if (a.setting != b.setting) continue;
        ++compared;
        EXPECT_NE(a.bytes, b.bytes) << name << " quality " << a.setting;
      }
    }
    EXPECT_GT(compared, 0) << name;
  }

  // Alone, svc-fast is what the anchors are ranked and measured against.
  options.codecs = {"jpeg", "svc-fast"};
  options.out_dir = dir_->path() / "fast-alone";
  auto alone = run_bench(options);
  ASSERT_TRUE(alone.ok()) << alone.status().to_string();
  EXPECT_EQ(alone->bd_reference, "svc-fast");
  const CodecResult& jpeg = alone->codecs[1];
  ASSERT_EQ(jpeg.name, "jpeg");
  ASSERT_GE(jpeg.reference_point, 0);
  const double target = alone->codecs[0].points[static_cast<size_t>(alone->codecs[0].reference_point)].psnr_y;
  for (const QualityPoint& p : jpeg.points) {
    EXPECT_LE(std::abs(jpeg.points[static_cast<size_t>(jpeg.reference_point)].psnr_y - target),
              std::abs(p.psnr_y - target) + 1e-9);
  }
}

TEST_F(BenchRun, ExperimentsCoverTheDissertationTables) {
  ASSERT_TRUE(results_ && results_->experiments);
  const Experiments& e = *results_->experiments;
  std::vector<std::string> names;
  for (const SizeRow& row : e.table_7_5) names.push_back(row.name);
  EXPECT_EQ(names, (std::vector<std::string>{"raw", "PNG", "JPEG", "MPEG-2 row-major", "spatial (svc)"}));
  EXPECT_EQ(e.table_7_5[0].bytes, results_->raw_bytes);
  ASSERT_EQ(e.b_to_i_sweep.size(), 5u);
  EXPECT_EQ(e.b_to_i_sweep[0].b_faces, 0u);  // every cell an I-cube
  EXPECT_EQ(e.b_to_i_sweep[0].i_faces, 24u);
  for (const SweepPoint& p : e.b_to_i_sweep) {
    EXPECT_EQ(p.i_faces + p.b_faces, 24u);
    EXPECT_GT(p.bytes, 0u);
  }
  ASSERT_FALSE(e.spacing_sweep.empty());
  EXPECT_EQ(e.spacing_sweep[0].sample_spacing, 1);
  ASSERT_EQ(e.table_7_4.size(), 2u);
  EXPECT_EQ(e.table_7_4[0].motion, "depth");
  EXPECT_EQ(e.table_7_4[1].motion, "logarithmic");
  for (const MotionRow& row : e.table_7_4) {
    EXPECT_GT(row.bytes_at_equal_psnr, 0) << row.motion;
    EXPECT_FALSE(row.points.empty());
  }
}

TEST_F(BenchRun, WritesCsvReportAndValidPngPlots) {
  ASSERT_TRUE(results_);
  std::istringstream csv(read_text(out() / "results.csv"));
  size_t rows = 0, expected = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  for (const CodecResult& c : results_->codecs) expected += c.points.size();
  EXPECT_EQ(rows, expected + 1);

  const std::string report = read_text(out() / "report.md");
  for (const char* name : {"rd_curves.png", "access_cost.png", "fig7_16.png"}) {
    EXPECT_NE(report.find(std::string("](") + name + ")"), std::string::npos) << name;
    const fs::path path = out() / name;
    ASSERT_TRUE(fs::exists(path)) << name;
    const std::string bytes = read_text(path);
    ASSERT_GT(bytes.size(), 8u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in) << name;
    EXPECT_GE(in->spec().width, 600) << name;
    EXPECT_GE(in->spec().height, 400) << name;
    std::vector<uint8_t> pixels(static_cast<size_t>(in->spec().width) * in->spec().height * 3);
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data())) << name;
  }
  EXPECT_NE(report.find("Table 7.5"), std::string::npos);
  EXPECT_NE(report.find("Table 7.4"), std::string::npos);
  EXPECT_FALSE(fs::exists(out() / "work"));  // scratch files are removed
  EXPECT_FALSE(progress_lines_.empty());
}

TEST(BenchOptionsTest, UnknownCodecIsRejected) {
  BenchOptions options;
  options.db_dir = "/nonexistent";
  options.out_dir = "/nonexistent-out";
  options.codecs = {"svc", "divx"};
  auto results = run_bench(options);
  ASSERT_FALSE(results.ok());
  EXPECT_EQ(results.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(results.status().message().find("divx"), std::string::npos);
}

TEST(BenchOptionsTest, BadPresetOrGopIsRejectedBeforeAnyWork) {
  testing::TempDir dir("svc-bench-options");
  BenchOptions options;
  options.db_dir = "/nonexistent";
  options.out_dir = dir.path() / "out";
  options.codecs = {"svc", "x265"};
  options.anchor_presets = {{"x265", "turbo"}};
  auto results = run_bench(options);
  ASSERT_FALSE(results.ok());
  EXPECT_EQ(results.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(results.status().message().find("turbo"), std::string::npos) << results.status().to_string();
  EXPECT_FALSE(fs::exists(options.out_dir));
  options.anchor_presets = {{"divx", "fast"}};
  EXPECT_NE(run_bench(options).status().message().find("divx"), std::string::npos);
  options.anchor_presets.clear();
  options.anchor_options = {{"divx", {{"x264-params", "no-deblock=1"}}}};
  EXPECT_NE(run_bench(options).status().message().find("divx"), std::string::npos);
  options.anchor_options = {{"svc", {{"aom-params", "enable-cdef=0"}}}};
  EXPECT_EQ(run_bench(options).status().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(options.out_dir));
  options.anchor_options.clear();
  options.gop = 0;
  EXPECT_EQ(run_bench(options).status().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(options.out_dir));
}

}  // namespace
}  // namespace svc::bench
