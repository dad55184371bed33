// SPDX-License-Identifier: BSD-2-Clause
// The pieces of `svc bench` that need no codec: chart drawing, BD-rate, JSON/CSV writers,
// and the subsampled manifest of the Figure 7.16 spacing sweep.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "database/database.h"
#include "plot.h"
#include "rd_curve.h"
#include "scene/scene.h"
#include "support/test_support.h"
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

bool is_dark(const ImageRGB8& image, int x, int y) {
  const uint8_t* p = &image.pixels[(static_cast<size_t>(y) * image.width + x) * 3];
  return p[0] < 128 && p[1] < 128 && p[2] < 128;
}

TEST(BenchPlot, LinearTicksAreRoundAndCoverTheRange) {
  EXPECT_EQ(plot::linear_ticks(0, 10, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  const auto ticks = plot::linear_ticks(31.3, 44.9, 6);
  ASSERT_FALSE(ticks.empty());
  EXPECT_DOUBLE_EQ(ticks.front(), 32);
  EXPECT_DOUBLE_EQ(ticks.back(), 44);
  for (size_t i = 1; i < ticks.size(); ++i) EXPECT_NEAR(ticks[i] - ticks[i - 1], 2.0, 1e-9);
  EXPECT_TRUE(plot::linear_ticks(3, 3).empty());
}

TEST(BenchPlot, LogTicksUseOneTwoFive) {
  EXPECT_EQ(plot::log_ticks(1, 100), (std::vector<double>{1, 2, 5, 10, 20, 50, 100}));
  EXPECT_EQ(plot::log_ticks(1, 9), (std::vector<double>{1, 1.5, 2, 3, 5, 7}));
  const auto wide = plot::log_ticks(0.09, 900);
  EXPECT_EQ(wide, (std::vector<double>{0.1, 1, 10, 100}));
  EXPECT_TRUE(plot::log_ticks(0, 10).empty());
  EXPECT_EQ(plot::tick_label(2.5), "2.5");
  EXPECT_EQ(plot::tick_label(1000), "1000");
  EXPECT_EQ(plot::tick_label(0.05), "0.05");
}

TEST(BenchPlot, LineCoversItsPixelsAndNothingFar) {
  plot::Canvas canvas(40, 20);
  canvas.line(5, 10.5, 35, 10.5, {0, 0, 0}, 2.0);
  EXPECT_TRUE(is_dark(canvas.image(), 20, 10));
  EXPECT_TRUE(is_dark(canvas.image(), 5, 10));
  EXPECT_FALSE(is_dark(canvas.image(), 20, 5));
  EXPECT_FALSE(is_dark(canvas.image(), 38, 10));
  // Drawing off the canvas is clipped, not a crash.
  canvas.line(-100, -100, 200, 300, {255, 0, 0}, 3.0);
}

TEST(BenchPlot, TextUsesTheBuiltInFont) {
  EXPECT_EQ(plot::text_width("ab", 2), (2 * 6 - 1) * 2);
  EXPECT_EQ(plot::text_height(3), 21);
  plot::Canvas canvas(20, 10);
  canvas.text(1, 1, "I", {0, 0, 0}, 1);
  // 'I' of the 5x7 font: a vertical bar in the middle column, serifs top and bottom.
  for (int row = 0; row < 7; ++row) EXPECT_TRUE(is_dark(canvas.image(), 1 + 2, 1 + row)) << row;
  EXPECT_TRUE(is_dark(canvas.image(), 1 + 1, 1));
  EXPECT_FALSE(is_dark(canvas.image(), 1 + 1, 1 + 3));
  EXPECT_FALSE(is_dark(canvas.image(), 1 + 0, 1 + 3));
}

TEST(BenchPlot, ChartIsWrittenAsReadablePng) {
  testing::TempDir dir("svc-bench-plot");
  plot::LineChart chart;
  chart.title = "PSNR";
  chart.x = {"bits per pixel", true, {}, {}};
  chart.y = {"dB", false, {}, {}};
  chart.series.push_back({"a", {{0.5, 30}, {1, 34}, {2, 38}}, false, {}});
  chart.series.push_back({"b", {{0.7, 31}, {1.4, 35}, {0, 40}}, true, {}});  // x = 0: not on a log axis
  plot::Canvas canvas(640, 400);
  plot::draw_line_chart(canvas, {0, 0, 640, 400}, chart);
  const fs::path path = dir.path() / "chart.png";
  ASSERT_TRUE(plot::write_png(canvas, path).ok());
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in);
  EXPECT_EQ(std::string(in->format_name()), "png");
  EXPECT_EQ(in->spec().width, 640);
  EXPECT_EQ(in->spec().height, 400);
  EXPECT_EQ(in->spec().nchannels, 3);
  std::vector<uint8_t> pixels(640 * 400 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
  EXPECT_EQ(pixels, canvas.image().pixels);
  // Something was drawn in the series' colors.
  const plot::Color first = plot::palette(0);
  bool found = false;
  for (size_t i = 0; i < pixels.size(); i += 3) {
    found |= pixels[i] == first.r && pixels[i + 1] == first.g && pixels[i + 2] == first.b;
  }
  EXPECT_TRUE(found);
  EXPECT_FALSE(plot::write_png(canvas, dir.path() / "missing-folder" / "x.png").ok());
}

TEST(BenchRd, BdRateOfAUniformlySmallerCodecIsItsRatio) {
  std::vector<RdPoint> anchor, test;
  for (int q = 0; q < 5; ++q) {
    const double bytes = 1000.0 * std::pow(1.6, q);
    const double psnr = 30.0 + 2.5 * q;
    anchor.push_back({q, bytes, psnr, 0});
    test.push_back({q, bytes * 0.8, psnr, 0});
  }
  const auto ratio = bd_rate_ratio(RdCurve(anchor), RdCurve(test));
  ASSERT_TRUE(ratio.has_value());
  EXPECT_NEAR(*ratio, 0.8, 1e-9);
  const auto inverse = bd_rate_ratio(RdCurve(test), RdCurve(anchor));
  EXPECT_NEAR(*inverse, 1.25, 1e-9);
  // No PSNR overlap: no BD-rate.
  std::vector<RdPoint> far = {{0, 10, 60, 0}, {1, 20, 70, 0}};
  EXPECT_FALSE(bd_rate_ratio(RdCurve(anchor), RdCurve(far)).has_value());
}

BenchResults sample_results() {
  BenchResults r;
  r.database = "db";
  r.grid = {3, 1, 3};
  r.cells = 9;
  r.faces = 54;
  r.face_width = r.face_height = 32;
  r.raw_bytes = 54 * 32 * 32 * 3;
  r.threads = 2;
  r.bd_reference = "svc";
  CodecResult svc;
  svc.name = "svc";
  svc.encoder = "svc";
  svc.points.push_back({"quality", 50, 4000, 41.472, 0.5787, 35.1, 37.25, 0.95, 0.1, 0.01});
  svc.points.push_back({"quality", 75, 8000, 20.736, 1.1574, 38.0, 41.5, 0.98, 0.2, 0.02});
  svc.reference_point = 1;
  svc.encode_faces_per_second = 270;
  svc.access_cold = {10, 1.5, 2.5, 1.9, 3};
  svc.access_warm = {10, 0.5, 0.7, 1.9, 3};
  CodecResult skipped;
  skipped.name = "av1";
  skipped.encoder = "";
  skipped.skipped = true;
  skipped.skip_reason = "no AV1 encoder in this build of libavcodec";
  CodecResult jpeg;
  jpeg.name = "jpeg";
  jpeg.encoder = "mjpeg";
  jpeg.points.push_back({"qscale", 3, 9000, 18.432, 1.3021, 36.0, 40.0, 0.97, 0.05, 0.02});
  jpeg.points.push_back({"qscale", 8, 5000, 33.1776, 0.7234, 32.0, 34.0, 0.93, 0.05, 0.02});
  jpeg.reference_point = 0;
  jpeg.bd_rate_svc = -0.25;
  r.codecs = {svc, skipped, jpeg};
  return r;
}

TEST(BenchWriters, JsonHoldsEveryCodecAndPoint) {
  testing::TempDir dir("svc-bench-json");
  const BenchResults r = sample_results();
  ASSERT_TRUE(write_results_json(r, dir.path() / "results.json").ok());
  const auto j = nlohmann::json::parse(read_text(dir.path() / "results.json"));
  EXPECT_EQ(j["format"], "svc-bench");
  EXPECT_EQ(j["database"]["raw_bytes"], r.raw_bytes);
  EXPECT_EQ(j["database"]["grid"], (std::vector<int>{3, 1, 3}));
  ASSERT_EQ(j["codecs"].size(), 3u);
  EXPECT_EQ(j["codecs"][0]["name"], "svc");
  EXPECT_EQ(j["codecs"][0]["points"].size(), 2u);
  EXPECT_EQ(j["codecs"][0]["points"][1]["bytes"], 8000);
  EXPECT_DOUBLE_EQ(j["codecs"][0]["points"][1]["psnr_y"].get<double>(), 41.5);
  EXPECT_DOUBLE_EQ(j["codecs"][0]["random_access"]["cold"]["mean_frames_decoded"].get<double>(), 1.9);
  EXPECT_EQ(j["bd_reference"], "svc");
  EXPECT_TRUE(j["codecs"][0]["bd_rate_svc"].is_null());
  EXPECT_TRUE(j["codecs"][1]["skipped"].get<bool>());
  EXPECT_EQ(j["codecs"][1]["skip_reason"], "no AV1 encoder in this build of libavcodec");
  EXPECT_DOUBLE_EQ(j["codecs"][2]["bd_rate_svc"].get<double>(), -0.25);
  EXPECT_TRUE(j["experiments"].is_null());
}

TEST(BenchWriters, CsvHasOneRowPerPoint) {
  testing::TempDir dir("svc-bench-csv");
  ASSERT_TRUE(write_results_csv(sample_results(), dir.path() / "results.csv").ok());
  std::istringstream csv(read_text(dir.path() / "results.csv"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 5u);  // header + 2 svc + 2 jpeg; the skipped codec has none
  EXPECT_EQ(lines[0],
            "codec,encoder,setting_name,setting,bytes,compression_ratio,bits_per_pixel,psnr_rgb,psnr_y,ssim,"
            "encode_seconds,decode_seconds");
  EXPECT_EQ(lines[1].rfind("svc,svc,quality,50,4000,41.4720,", 0), 0u) << lines[1];
  EXPECT_EQ(lines[4].rfind("jpeg,mjpeg,qscale,8,5000,", 0), 0u) << lines[4];
  EXPECT_FALSE(write_results_csv(sample_results(), dir.path() / "no" / "such" / "dir.csv").ok());
}

TEST(BenchWriters, RankingPutsTheBetterCodecsFirstAndNamesWhereSvcLoses) {
  BenchResults r = sample_results();
  CodecResult x265;
  x265.name = "x265";
  x265.description = "GOP 9, 2 B-frames, open GOP, preset medium";
  x265.points = r.codecs[2].points;
  x265.bd_rate_svc = 0.15;
  x265.bd_range_y = {31.0, 41.0};
  x265.bd_rate_svc_target = 0.14;
  x265.bd_range_target = {32.0, 40.0};
  x265.bd_rate_svc_rgb = 0.12;
  x265.bd_range_rgb = {31.5, 36.0};
  x265.access_cold = {10, 1.0, 2.0, 4.36, 10};
  r.codecs.push_back(x265);
  const std::string md = ranking_markdown(r);
  const size_t x265_row =
      md.find("| 1 | x265 | +15.0% (31.0-41.0 dB) | +14.0% (32.0-40.0 dB) | +12.0% (31.5-36.0 dB) |");
  const size_t svc_row = md.find("| 2 | svc | 0 (reference)");
  const size_t jpeg_row = md.find("| 3 | jpeg | -25.0%");
  EXPECT_NE(x265_row, std::string::npos) << md;
  EXPECT_NE(svc_row, std::string::npos) << md;
  EXPECT_NE(jpeg_row, std::string::npos) << md;
  EXPECT_LT(x265_row, svc_row);
  EXPECT_LT(svc_row, jpeg_row);
  EXPECT_NE(md.find("4.36 (max 10)"), std::string::npos) << md;
  EXPECT_NE(md.find("GOP 9, 2 B-frames, open GOP, preset medium"), std::string::npos) << md;
  EXPECT_NE(md.find("**svc loses to x265 (+15.0%)**"), std::string::npos) << md;
  EXPECT_NE(md.find("svc is smaller than jpeg (-25.0%)"), std::string::npos) << md;
  EXPECT_EQ(md.find("| av1 |"), std::string::npos) << "a skipped codec has no rank";
}

TEST(BenchWriters, RankingIsAgainstTheSvcLayoutThatRanWhenSvcDidNot) {
  BenchResults r = sample_results();
  r.codecs[0].name = "svc-intra";
  r.bd_reference = "svc-intra";
  const std::string md = ranking_markdown(r);
  EXPECT_NE(md.find("BD-rate of svc-intra, PSNR-Y (range)"), std::string::npos) << md;
  EXPECT_NE(md.find("| svc-intra | 0 (reference)"), std::string::npos) << md;
  EXPECT_NE(md.find("svc-intra needs fewer bytes than every anchor here"), std::string::npos) << md;
  r.bd_reference.clear();
  EXPECT_NE(ranking_markdown(r).find("No svc layout ran"), std::string::npos);
}

TEST(BenchWriters, SummaryTableShowsBdRateAndSkips) {
  const std::string table = summary_table_markdown(sample_results());
  EXPECT_NE(table.find("| svc | quality 75 |"), std::string::npos) << table;
  EXPECT_NE(table.find("-25.0%"), std::string::npos) << table;
  EXPECT_NE(table.find("| av1 | skipped: no AV1 encoder"), std::string::npos) << table;
}

TEST(BenchSubsample, KeepsEveryNthCellAndItsFiles) {
  testing::TempDir dir("svc-bench-subsample");
  samples::SceneOptions options;
  options.grid = {3, 1, 3};
  options.face_size = 16;
  const fs::path db = dir.path() / "db";
  ASSERT_TRUE(samples::generate_scene(options, db).ok());
  const fs::path sub = dir.path() / "sub";
  ASSERT_TRUE(write_subsampled_manifest(db, 2, sub).ok());

  auto original = load_manifest(db);
  auto thinned = load_manifest(sub, ManifestOptions{.allow_outside_paths = true});
  ASSERT_TRUE(original.ok());
  ASSERT_TRUE(thinned.ok()) << thinned.status().to_string();
  EXPECT_EQ(thinned->grid.dims, (std::array<int32_t, 3>{2, 1, 2}));
  EXPECT_DOUBLE_EQ(thinned->grid.spacing[0], original->grid.spacing[0] * 2);
  EXPECT_DOUBLE_EQ(thinned->grid.spacing[1], original->grid.spacing[1]);
  ASSERT_EQ(thinned->cells.size(), 4u);
  // Cell (1,0,1) of the thinned grid is cell (2,0,2) of the original, same pixels.
  const auto t = find_cell(*thinned, CellIndex{1, 0, 1});
  const auto o = find_cell(*original, CellIndex{2, 0, 2});
  ASSERT_TRUE(t && o);
  auto a = load_face(*thinned, *t, Face::kPZ);
  auto b = load_face(*original, *o, Face::kPZ);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->color.pixels, b->color.pixels);
  EXPECT_EQ(thinned->cells[*t].position, original->cells[*o].position);

  EXPECT_EQ(write_subsampled_manifest(db, 0, sub).code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace svc::bench
