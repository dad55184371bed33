// SPDX-License-Identifier: BSD-2-Clause
// Incremental additions (svc add): new cells appended without touching old ones, and
// crash safety of the in-place commit, checked by killing an adding child process.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "codec/common/depth.h"
#include "database/database.h"
#include "output/updater.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

extern char** environ;

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

void write_bytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A database that lists only the cells of `full` for which `keep` holds, with grid dims
// `dims`, holding copies of their image files (a manifest may not reach outside its folder).
void write_partial_database(const fs::path& full, const fs::path& out, const std::array<int, 3>& dims,
                            const std::function<bool(const json& index)>& keep) {
  std::ifstream in(full / "manifest.json");
  json manifest = json::parse(in);
  json cells = json::array();
  for (json cell : manifest["cells"]) {
    if (!keep(cell["index"])) continue;
    for (auto& [name, face] : cell["faces"].items()) {
      for (const char* key : {"color", "depth"}) {
        const std::string path = face[key].get<std::string>();
        fs::create_directories((out / path).parent_path());
        fs::copy_file(full / path, out / path, fs::copy_options::overwrite_existing);
      }
    }
    cells.push_back(cell);
  }
  manifest["cells"] = cells;
  manifest["grid"]["dims"] = dims;
  fs::create_directories(out);
  std::ofstream(out / "manifest.json") << manifest.dump(1);
}

using DecodedFaces = std::map<std::pair<std::array<int32_t, 3>, int>, ImageYCbCr420>;

// Every face of the file, decoded.
DecodedFaces decode_all(const fs::path& file) {
  DecodedFaces faces;
  auto reader = Reader::open(file);
  EXPECT_TRUE(reader.ok()) << reader.status().to_string();
  if (!reader.ok()) return faces;
  for (const CellEntry& cell : (*reader)->cells()) {
    for (Face face : kAllFaces) {
      auto image = (*reader)->decode_face_ycbcr(cell.index, face);
      EXPECT_TRUE(image.ok()) << image.status().to_string();
      if (image.ok()) faces[{{cell.index.x, cell.index.y, cell.index.z}, static_cast<int>(face)}] = *image;
    }
  }
  return faces;
}

bool same_image(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  return a.width == b.width && a.height == b.height && a.y == b.y && a.cb == b.cb && a.cr == b.cr;
}

// Scene shared by the tests: a 4x1x3 grid of 16-pixel faces. `part` holds the cells
// with x < 2 (grid 2x1x3), `full` all of them.
class Add : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-add");
    samples::SceneOptions options;
    options.grid = {4, 1, 3};
    options.face_size = 16;
    ASSERT_TRUE(samples::generate_scene(options, full()).ok());
    write_partial_database(full(), part(), {2, 1, 3}, [](const json& i) { return i[0].get<int>() < 2; });
    EncoderSettings settings;
    settings.threads = 1;
    ASSERT_TRUE(encode_database(part(), base(), settings).ok());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path full() { return dir_->path() / "full"; }
  static fs::path part() { return dir_->path() / "part"; }
  static fs::path base() { return dir_->path() / "part.svc"; }
  // A fresh copy of the encoded part, to add to.
  static fs::path copy_of_base(const std::string& name) {
    const fs::path path = dir_->path() / name;
    fs::remove(path);
    fs::copy_file(base(), path);
    return path;
  }
  static testing::TempDir* dir_;
};
testing::TempDir* Add::dir_ = nullptr;

TEST_F(Add, AddsNewCellsAndOldCellsDecodeBitExact) {
  const fs::path file = copy_of_base("grown.svc");
  const uint64_t size_before = fs::file_size(file);
  const DecodedFaces before = decode_all(file);
  auto reader_before = Reader::open(file);
  ASSERT_TRUE(reader_before.ok());
  const std::vector<CellEntry> old_cells = (*reader_before)->cells();
  reader_before->reset();

  AddSettings settings;
  settings.threads = 2;
  uint64_t last_done = 0, last_total = 0;
  auto summary = add_to_database(file, full(), settings, [&](uint64_t done, uint64_t total) {
    last_done = done;
    last_total = total;
    return true;
  });
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_EQ(summary->cells_before, 6u);
  EXPECT_EQ(summary->cells_added, 6u);
  EXPECT_EQ(summary->cells_present, 6u);
  EXPECT_EQ(summary->faces_added, 36u);
  EXPECT_EQ(last_done, 36u);
  EXPECT_EQ(last_total, 36u);
  EXPECT_EQ(summary->generation, 2u);
  EXPECT_EQ(summary->grid_dims, (std::array<int32_t, 3>{4, 1, 3}));
  // The figures are the file's growth: face chunks and the new index together.
  EXPECT_EQ(summary->file_bytes, fs::file_size(file));
  EXPECT_EQ(summary->bytes_appended, fs::file_size(file) - size_before);
  // x = 3 lies in a group of its own whose nominal I-cube (x = 4) is outside the grid:
  // the nearest present cell, (3,0,1), becomes its I-cube; the rest are B-cubes.
  EXPECT_EQ(summary->intra_cells_added, 1u);
  EXPECT_EQ(summary->predicted_cells_added, 5u);

  auto reader = Reader::open(file);
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  EXPECT_EQ((*reader)->info().grid_dims, (std::array<int32_t, 3>{4, 1, 3}));
  ASSERT_EQ((*reader)->cells().size(), 12u);
  EXPECT_TRUE((*reader)->verify().ok()) << (*reader)->verify().to_string();
  // Old cells: same chunks, same type, same references (by cell index), same pixels.
  for (const CellEntry& old : old_cells) {
    const auto ordinal = (*reader)->find_cell(old.index);
    ASSERT_TRUE(ordinal.has_value());
    const CellEntry& now = (*reader)->cells()[*ordinal];
    for (int f = 0; f < kFaceCount; ++f) {
      EXPECT_EQ(now.faces[f].offset, old.faces[f].offset);
      EXPECT_EQ(now.faces[f].type, old.faces[f].type);
      ASSERT_EQ(now.faces[f].references.size(), old.faces[f].references.size());
      for (size_t r = 0; r < old.faces[f].references.size(); ++r) {
        const CellIndex was = old_cells[old.faces[f].references[r].first].index;
        const CellIndex is = (*reader)->cells()[now.faces[f].references[r].first].index;
        EXPECT_TRUE(was.x == is.x && was.y == is.y && was.z == is.z);
      }
    }
  }
  const DecodedFaces after = decode_all(file);
  for (const auto& [key, image] : before) {
    ASSERT_TRUE(after.count(key));
    EXPECT_TRUE(same_image(after.at(key), image)) << "cell x " << key.first[0] << " z " << key.first[2];
  }
  // A new B-cube at x = 2 predicts from the old I-cube (1,0,1) and the new one (3,0,1).
  const CellEntry& b = (*reader)->cells()[*(*reader)->find_cell({2, 0, 1})];
  EXPECT_EQ(b.faces[0].type, FaceType::kPredicted);
  std::set<int> ref_x;
  for (const auto& [cell, face] : b.faces[0].references) ref_x.insert((*reader)->cells()[cell].index.x);
  EXPECT_EQ(ref_x, (std::set<int>{1, 3}));

  // New cells decode close to a from-scratch encode of the whole database.
  const fs::path scratch = dir_->path() / "scratch.svc";
  EncoderSettings encode_settings;
  encode_settings.threads = 1;
  ASSERT_TRUE(encode_database(full(), scratch, encode_settings).ok());
  const DecodedFaces reference = decode_all(scratch);
  ASSERT_EQ(reference.size(), after.size());
  for (const auto& [key, image] : after) {
    double error = 0;
    const ImageYCbCr420& expected = reference.at(key);
    for (size_t i = 0; i < image.y.size(); ++i) error += std::abs(int(image.y[i]) - int(expected.y[i]));
    EXPECT_LT(error / image.y.size(), 12.0) << "cell x " << key.first[0] << " z " << key.first[2];
  }
}

// A file with depth grows with depth: the new faces' depth decodes exactly (lossless),
// and the old faces' depth is untouched.
TEST_F(Add, AddsDepthToAFileWithDepth) {
  EncoderSettings encode;
  encode.threads = 1;
  encode.depth = true;
  const fs::path file = dir_->path() / "depth.svc";
  ASSERT_TRUE(encode_database(part(), file, encode).ok());
  AddSettings settings;
  settings.threads = 2;
  auto summary = add_to_database(file, full(), settings);
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  auto manifest = load_manifest(full());
  ASSERT_TRUE(manifest.ok());
  auto reader = Reader::open(file);
  ASSERT_TRUE(reader.ok());
  ASSERT_TRUE((*reader)->info().has_depth);
  EXPECT_TRUE((*reader)->verify().ok());
  for (size_t c = 0; c < manifest->cells.size(); ++c) {
    for (Face face : kAllFaces) {
      auto source = load_face(*manifest, c, face);
      ASSERT_TRUE(source.ok());
      auto depth = (*reader)->decode_face_depth(manifest->cells[c].index, face);
      ASSERT_TRUE(depth.ok()) << depth.status().to_string();
      const auto entry = (*reader)->find_cell(manifest->cells[c].index);
      ASSERT_TRUE(entry.has_value());
      const double near_plane = (*reader)->cells()[*entry].cameras[static_cast<int>(face)].frustum.near_plane;
      for (size_t i = 0; i < depth->size(); ++i) {
        ASSERT_EQ(codec::inverse_depth_code((*depth)[i], near_plane),
                  codec::inverse_depth_code(source->depth[i], near_plane))
            << face_label(manifest->cells[c].index, face) << " pixel " << i;
      }
    }
  }
}

TEST_F(Add, NothingNewLeavesTheFileUntouched) {
  const fs::path file = copy_of_base("same.svc");
  const std::vector<uint8_t> before = testing::read_file_data(file);
  auto summary = add_to_database(file, part());
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_EQ(summary->cells_added, 0u);
  EXPECT_EQ(summary->cells_present, 6u);
  EXPECT_EQ(testing::read_file_data(file), before);
}

TEST_F(Add, TwoAddsInARowUseBothCommitSlots) {
  const fs::path file = copy_of_base("twice.svc");
  const fs::path three = dir_->path() / "three";
  write_partial_database(full(), three, {3, 1, 3}, [](const json& i) { return i[0].get<int>() < 3; });
  auto first = add_to_database(file, three);
  ASSERT_TRUE(first.ok()) << first.status().to_string();
  EXPECT_EQ(first->cells_added, 3u);
  EXPECT_EQ(first->generation, 2u);
  const DecodedFaces middle = decode_all(file);
  auto second = add_to_database(file, full());
  ASSERT_TRUE(second.ok()) << second.status().to_string();
  EXPECT_EQ(second->cells_added, 3u);
  EXPECT_EQ(second->generation, 3u);
  const DecodedFaces after = decode_all(file);
  for (const auto& [key, image] : middle) EXPECT_TRUE(same_image(after.at(key), image));
  auto reader = Reader::open(file);
  ASSERT_TRUE(reader.ok());
  EXPECT_TRUE((*reader)->verify().ok());
}

TEST_F(Add, RejectsIncompatibleDatabases) {
  const fs::path file = copy_of_base("mismatch.svc");
  const std::vector<uint8_t> before = testing::read_file_data(file);
  // Other face size.
  samples::SceneOptions options;
  options.grid = {1, 1, 1};
  options.face_size = 32;
  const fs::path big = dir_->path() / "big";
  ASSERT_TRUE(samples::generate_scene(options, big).ok());
  auto result = add_to_database(file, big);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), ErrorCode::kBadInput);
  EXPECT_NE(result.status().message().find("32x32"), std::string::npos) << result.status().message();
  // Other grid spacing and origin.
  for (const char* field : {"spacing", "origin"}) {
    std::ifstream in(full() / "manifest.json");
    json manifest = json::parse(in);
    manifest["grid"][field][0] = manifest["grid"][field][0].get<double>() + 0.25;
    const fs::path shifted = dir_->path() / (std::string("shifted-") + field);
    write_partial_database(full(), shifted, {4, 1, 3}, [](const json&) { return true; });
    std::ifstream shifted_in(shifted / "manifest.json");
    json shifted_manifest = json::parse(shifted_in);
    shifted_manifest["grid"] = manifest["grid"];
    std::ofstream(shifted / "manifest.json") << shifted_manifest.dump(1);
    result = add_to_database(file, shifted);
    ASSERT_FALSE(result.ok()) << field;
    EXPECT_NE(result.status().message().find(std::string("grid ") + field), std::string::npos)
        << result.status().message();
  }
  // Not an .svc file, a missing database.
  EXPECT_FALSE(add_to_database(part() / "manifest.json", full()).ok());
  EXPECT_EQ(add_to_database(file, dir_->path() / "missing").status().code(), ErrorCode::kNotFound);
  EXPECT_EQ(testing::read_file_data(file), before);
}

TEST_F(Add, ASecondUpdaterIsRefusedWhileOneHoldsTheFile) {
  const fs::path file = copy_of_base("locked.svc");
  auto first = ContainerUpdater::open(file);
  ASSERT_TRUE(first.ok()) << first.status().to_string();
  auto second = ContainerUpdater::open(file);
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.status().message().find("another process"), std::string::npos);
  // Appending without a commit leaves the file as it was once the updater goes away.
  const std::vector<uint8_t> before = testing::read_file_data(file);
  const std::vector<uint8_t> payload(100, 7);
  ASSERT_TRUE((*first)->append_frame(payload).ok());
  EXPECT_GT(fs::file_size(file), before.size());
  first->reset();
  EXPECT_EQ(testing::read_file_data(file), before);
}

// --- Crash safety ---------------------------------------------------------------------

// The child side: runs when the test program is started with SVC_TEST_ADD_CHILD set to
// "SVC_FILE\nDB_DIR\nKILL_AFTER_BYTES" (a negative count: no fault injection).
TEST(AddChild, RunsAddAndMayBeKilled) {
  const char* spec = std::getenv("SVC_TEST_ADD_CHILD");
  if (spec == nullptr) GTEST_SKIP() << "child side of Add.KilledAtAnyPointLeavesTheOldDatabase";
  std::istringstream in(spec);
  std::string file, db, kill_after;
  std::getline(in, file);
  std::getline(in, db);
  std::getline(in, kill_after);
  set_updater_kill_after_bytes_for_testing(std::stoll(kill_after));
  AddSettings settings;
  settings.threads = 1;
  auto summary = add_to_database(file, db, settings);
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
}

// Starts this test program as a child that adds `db` to `file`; returns its pid.
pid_t spawn_add_child(const fs::path& file, const fs::path& db, int64_t kill_after) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::string env_spec =
      "SVC_TEST_ADD_CHILD=" + file.string() + "\n" + db.string() + "\n" + std::to_string(kill_after);
  std::vector<std::string> env_strings = {env_spec};
  for (char** e = environ; *e; ++e) {
    if (std::string(*e).rfind("SVC_TEST_ADD_CHILD=", 0) != 0) env_strings.emplace_back(*e);
  }
  std::vector<char*> envp;
  for (auto& e : env_strings) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::string filter = "--gtest_filter=AddChild.RunsAddAndMayBeKilled";
  std::string quiet = "--gtest_brief=1";
  char* argv[] = {const_cast<char*>(self.c_str()), filter.data(), quiet.data(), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv, envp.data());
  posix_spawn_file_actions_destroy(&actions);
  EXPECT_EQ(rc, 0);
  return pid;
}

// Waits for the child; returns its wait status.
int wait_child(pid_t pid) {
  int status = 0;
  EXPECT_EQ(waitpid(pid, &status, 0), pid);
  return status;
}

TEST_F(Add, KilledAtAnyPointLeavesTheOldDatabase) {
  const DecodedFaces old_faces = decode_all(base());
  // A clean add, for the number of bytes an add writes and the bytes it leaves.
  const fs::path clean = copy_of_base("clean.svc");
  auto clean_summary = add_to_database(clean, full());
  ASSERT_TRUE(clean_summary.ok());
  const std::vector<uint8_t> clean_bytes = testing::read_file_data(clean);
  const int64_t total_written = static_cast<int64_t>(clean_summary->bytes_appended + kCommitSlotSize);

  auto expect_old_database = [&](const fs::path& file, const std::string& when) {
    auto reader = Reader::open(file);
    ASSERT_TRUE(reader.ok()) << when << ": " << reader.status().to_string();
    ASSERT_EQ((*reader)->cells().size(), 6u) << when;
    const DecodedFaces now = decode_all(file);
    ASSERT_EQ(now.size(), old_faces.size()) << when;
    for (const auto& [key, image] : old_faces) EXPECT_TRUE(same_image(now.at(key), image)) << when;
  };

  // Fault injection: the child kills itself after N bytes, for N across the whole add
  // (every face chunk, the index, fsyncs) and at every byte of the commit-slot write.
  std::vector<int64_t> kill_points;
  for (int k = 0; k < 16; ++k) kill_points.push_back(total_written * k / 16);
  for (int64_t n = total_written - static_cast<int64_t>(kCommitSlotSize); n < total_written; n += 4) {
    kill_points.push_back(n);
  }
  kill_points.push_back(total_written - 1);
  const fs::path file = dir_->path() / "killed.svc";
  int killed = 0;
  for (int64_t n : kill_points) {
    fs::remove(file);
    fs::copy_file(base(), file);
    const int status = wait_child(spawn_add_child(file, full(), n));
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "kill point " << n << " status " << status;
    ++killed;
    expect_old_database(file,
                        "killed after " + std::to_string(n) + " of " + std::to_string(total_written) + " bytes");
    if (n % 3 == 0 || n == total_written - 1) {
      // A retry after the crash cuts the leftovers off and writes what a clean add writes.
      auto retry = add_to_database(file, full());
      ASSERT_TRUE(retry.ok()) << retry.status().to_string();
      EXPECT_EQ(testing::read_file_data(file), clean_bytes) << "retry after a kill at " << n;
    }
  }
  EXPECT_EQ(killed, static_cast<int>(kill_points.size()));

  // Real kills from outside at random moments of an unmodified child: either the add
  // finished (the new database) or the old one is intact.
  // Delays spread over the time a whole child run takes.
  fs::remove(file);
  fs::copy_file(base(), file);
  const auto started = std::chrono::steady_clock::now();
  ASSERT_TRUE(WIFEXITED(wait_child(spawn_add_child(file, full(), -1))));
  const auto run_time =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - started);
  EXPECT_EQ(testing::read_file_data(file), clean_bytes);
  std::mt19937 random(7);
  int finished = 0, interrupted = 0;
  for (int round = 0; round < 6; ++round) {
    fs::remove(file);
    fs::copy_file(base(), file);
    const pid_t pid = spawn_add_child(file, full(), -1);
    std::this_thread::sleep_for(std::chrono::microseconds(random() % (run_time.count() * 11 / 10 + 1)));
    ::kill(pid, SIGKILL);
    const int status = wait_child(pid);
    auto reader = Reader::open(file);
    ASSERT_TRUE(reader.ok()) << reader.status().to_string();
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      ++finished;
      EXPECT_EQ(testing::read_file_data(file), clean_bytes);
    } else {
      ++interrupted;
      if ((*reader)->cells().size() == 12u) {
        EXPECT_EQ(testing::read_file_data(file), clean_bytes);  // killed after the commit landed
      } else {
        expect_old_database(file, "random kill in round " + std::to_string(round));
      }
    }
  }
  std::printf("random kills: %d interrupted, %d finished first\n", interrupted, finished);
}

}  // namespace
}  // namespace svc
