#include "cli/cli_util.h"

#include <cstdio>
#include <sstream>

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include "command_line/command_line.h"

namespace svc::cli {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(uint64_t done, uint64_t total) {
  if (!enabled_ || total == 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  drawn_ = true;
  const int width = 30;
  const double fraction = static_cast<double>(done) / static_cast<double>(total);
  const int filled = static_cast<int>(fraction * width);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = done > 0 ? elapsed * (static_cast<double>(total) - done) / done : 0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %llu/%llu %3.0f%%  %.1fs elapsed, %.1fs left ", label_.c_str(), filled,
               "##############################", width - filled, "", static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(total), fraction * 100.0, elapsed, eta);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (enabled_ && drawn_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
  drawn_ = false;
}

int report_error(const Status& status) {
  std::fprintf(stderr, "svc: %s\n", status.to_string().c_str());
  switch (status.code()) {
    case ErrorCode::kInvalidArgument: return command_line::kExitUsage;
    case ErrorCode::kCorruptData: return command_line::kExitCorrupt;
    default: return command_line::kExitFailure;
  }
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

Result<ImageRGB8> read_rgb(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return Status(ErrorCode::kIoError, "cannot read " + path.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  ImageRGB8 image;
  image.width = spec.width;
  image.height = spec.height;
  image.pixels.resize(static_cast<size_t>(spec.width) * spec.height * 3);
  if (spec.nchannels < 3 || !in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, image.pixels.data())) {
    return Status(ErrorCode::kIoError, "cannot read RGB from " + path.string());
  }
  return image;
}

}  // namespace svc::cli
