// Shared pieces of the svc command-line tool.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "svc/status.h"
#include "svc/types.h"

namespace svc::cli {

// A one-line progress bar on stderr, drawn only when stderr is a terminal.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();
  void update(uint64_t done, uint64_t total);
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

// Prints "svc: <message>" on stderr and returns the exit status for it.
int report_error(const Status& status);

// "X,Y,Z" -> CellIndex.
bool parse_cell(const std::string& text, CellIndex* out);
// "X,Y,Z" or "N" (all axes) -> three positive integers.
bool parse_triple(const std::string& text, std::array<int32_t, 3>* out);

std::string human_bytes(uint64_t bytes);

// Writes an 8-bit RGB PNG.
Status write_png(const std::filesystem::path& path, const ImageRGB8& image);
// Reads an image as 8-bit RGB (through the svc-input colour rules).
Result<ImageRGB8> read_rgb(const std::filesystem::path& path);

}  // namespace svc::cli
