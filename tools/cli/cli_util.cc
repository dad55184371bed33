// SPDX-License-Identifier: BSD-2-Clause
#include "cli/cli_util.h"

#include <cstdio>
#include <sstream>

#include <OpenImageIO/imageio.h>

#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/report.h"

namespace svc::cli {

int report_error(const Status& status) { return command_line::report_failure("svc", status); }

bool keep_going() { return !command_line::interrupted(); }

// Flushed at once: errors written to stderr after it never land inside the document when
// both streams go to one pipe.
void print_json(const json& value) {
  std::printf("%s\n", value.dump(2).c_str());
  std::fflush(stdout);
}

json face_type_stats_json(const FaceTypeStats& s) {
  json j;
  j["faces"] = s.faces;
  j["bytes"] = s.bytes;
  j["macroblocks"] = {{"intra", s.mb_intra},
                      {"forward", s.mb_forward},
                      {"backward", s.mb_backward},
                      {"bidirectional", s.mb_bidirectional},
                      {"skipped", s.mb_skipped}};
  j["mean_unique_candidates_per_macroblock"] =
      s.candidate_macroblocks ? static_cast<double>(s.candidate_vectors) / s.candidate_macroblocks : 0.0;
  return j;
}

void print_face_type_stats(const char* name, const FaceTypeStats& s) {
  if (s.faces == 0) return;
  std::printf("  %-9s %6llu faces  %10s", name, static_cast<unsigned long long>(s.faces),
              human_bytes(s.bytes).c_str());
  if (s.mb_forward + s.mb_backward + s.mb_bidirectional + s.mb_skipped > 0) {
    std::printf("  macroblocks: intra %llu, forward %llu, backward %llu, bidirectional %llu, skipped %llu",
                static_cast<unsigned long long>(s.mb_intra), static_cast<unsigned long long>(s.mb_forward),
                static_cast<unsigned long long>(s.mb_backward), static_cast<unsigned long long>(s.mb_bidirectional),
                static_cast<unsigned long long>(s.mb_skipped));
    if (s.candidate_macroblocks) {
      std::printf("; %.2f unique candidates/macroblock",
                  static_cast<double>(s.candidate_vectors) / s.candidate_macroblocks);
    }
  }
  std::printf("\n");
}

bool parse_cell(const std::string& text, CellIndex* out) {
  std::istringstream in(text);
  char c1 = 0, c2 = 0;
  int x, y, z;
  if (!(in >> x >> c1 >> y >> c2 >> z) || c1 != ',' || c2 != ',') return false;
  in >> std::ws;
  if (!in.eof()) return false;
  *out = CellIndex{x, y, z};
  return true;
}

bool parse_triple(const std::string& text, std::array<int32_t, 3>* out) {
  CellIndex c;
  if (parse_cell(text, &c)) {
    *out = {c.x, c.y, c.z};
  } else {
    std::istringstream in(text);
    int n;
    if (!(in >> n)) return false;
    in >> std::ws;
    if (!in.eof()) return false;
    *out = {n, n, n};
  }
  return (*out)[0] > 0 && (*out)[1] > 0 && (*out)[2] > 0;
}

std::string cell_folder(const CellIndex& cell) {
  return "cells/" + std::to_string(cell.x) + "_" + std::to_string(cell.y) + "_" + std::to_string(cell.z);
}

std::string comma_list(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

std::string human_bytes(uint64_t bytes) {
  char buf[64];
  if (bytes >= (1ull << 30)) {
    std::snprintf(buf, sizeof buf, "%.2f GiB", bytes / double(1ull << 30));
  } else if (bytes >= (1ull << 20)) {
    std::snprintf(buf, sizeof buf, "%.2f MiB", bytes / double(1ull << 20));
  } else if (bytes >= 1024) {
    std::snprintf(buf, sizeof buf, "%.1f KiB", bytes / 1024.0);
  } else {
    std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
  }
  return buf;
}

Status write_png(const std::filesystem::path& path, const ImageRGB8& image) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data()) ||
      !out->close()) {
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

}  // namespace svc::cli
