// The svc tool as a user runs it: what it prints, its exit codes, and what it refuses
// to write. Runs the built build/bin/svc.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <sys/wait.h>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// Runs build/bin/PROGRAM ARGS in `dir`; returns its exit code and what it printed.
CliRun run_program(const std::string& program, const std::string& args, const fs::path& dir) {
  const std::string command =
      "cd " + quoted(dir) + " && " + quoted(fs::path(SVC_BINARY_DIR) / "bin" / program) + " " + args + " 2>&1";
  CliRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) run.output.append(buffer, n);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

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

TEST_F(Cli, InfoOfAQscaleFileShowsTheScaleAndNoQuality) {
  const fs::path file = work("qscale.svc");
  ASSERT_EQ(run_svc("encode --quiet --qscale 20 " + quoted(db()) + " -o " + quoted(file)).exit_code, 0);
  const CliRun info = run_svc("info " + quoted(file));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("quantiser scale 20"), std::string::npos) << info.output;
  EXPECT_EQ(info.output.find("quality"), std::string::npos) << info.output;
  const CliRun json = run_svc("info --json " + quoted(file));
  EXPECT_NE(json.output.find("\"quality\": null"), std::string::npos) << json.output;
  EXPECT_NE(json.output.find("\"quant_scale\": 20"), std::string::npos) << json.output;

  const fs::path by_quality = work("quality.svc");
  ASSERT_EQ(run_svc("encode --quiet -q 60 " + quoted(db()) + " -o " + quoted(by_quality)).exit_code, 0);
  const CliRun quality_info = run_svc("info " + quoted(by_quality));
  EXPECT_NE(quality_info.output.find("quality 60, quantiser scale " + std::to_string(quant_scale_for_quality(60))),
            std::string::npos)
      << quality_info.output;
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

}  // namespace
}  // namespace svc
