// svc inspect: a decoded face beside its macroblock classification (intra red,
// predicted green, skipped blue), as in the dissertation's Figure 4.5.
#include <cstdio>
#include <map>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/output_paths.h"
#include "svc/reader.h"

namespace svc::cli {

using command_line::check_output;
using command_line::OutputKind;

namespace {

const char* mode_name(MacroblockCoding mode) {
  switch (mode) {
    case MacroblockCoding::kIntra: return "intra";
    case MacroblockCoding::kForward: return "forward";
    case MacroblockCoding::kBackward: return "backward";
    case MacroblockCoding::kBidirectional: return "bidirectional";
    case MacroblockCoding::kSkipped: return "skipped";
  }
  return "other";
}

// Intra red, any prediction green, skipped blue.
std::array<int, 3> mode_colour(MacroblockCoding mode) {
  switch (mode) {
    case MacroblockCoding::kIntra: return {230, 40, 40};
    case MacroblockCoding::kSkipped: return {40, 90, 240};
    default: return {40, 200, 60};
  }
}

}  // namespace

int inspect_command(const InspectOptions& options) {
  const Status writable = check_output(options.output, OutputKind::kFile, options.overwrite, {options.input});
  if (!writable.ok()) return report_error(writable);
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  auto inspected = (*reader)->inspect_face(options.cell, options.face);
  if (!inspected.ok()) return report_error(inspected.status());
  const ImageRGB8& face = inspected->image;
  const int w = face.width, h = face.height, mbw = inspected->macroblocks_x;
  const std::vector<MacroblockCoding>& modes = inspected->modes;
  const std::vector<uint8_t>& rgb = face.pixels;
  // Left: the decoded face. Right: the same face, dimmed, tinted by macroblock mode,
  // with the macroblock grid drawn.
  const int gap = 8;
  ImageRGB8 sheet;
  sheet.width = 2 * w + gap;
  sheet.height = h;
  sheet.pixels.assign(static_cast<size_t>(sheet.width) * h * 3, 255);
  std::map<int, uint64_t> counts;
  for (MacroblockCoding m : modes) counts[static_cast<int>(m)] += 1;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint8_t* src = &rgb[(static_cast<size_t>(y) * w + x) * 3];
      uint8_t* left = &sheet.pixels[(static_cast<size_t>(y) * sheet.width + x) * 3];
      uint8_t* right = &sheet.pixels[(static_cast<size_t>(y) * sheet.width + w + gap + x) * 3];
      const auto colour = mode_colour(modes[static_cast<size_t>(y / 16) * mbw + x / 16]);
      const bool edge = x % 16 == 0 || y % 16 == 0;
      for (int c = 0; c < 3; ++c) {
        left[c] = src[c];
        right[c] = edge ? static_cast<uint8_t>(colour[c]) : static_cast<uint8_t>((src[c] * 2 + colour[c] * 3) / 5);
      }
    }
  }
  Status status = write_png(options.output, sheet);
  if (!status.ok()) return report_error(status);
  std::printf("%s: %s-face, %zu macroblocks:", face_label(options.cell, options.face).c_str(),
              inspected->type == FaceType::kIntra ? "I" : "B", modes.size());
  for (const auto& [mode, count] : counts) {
    std::printf(" %s %llu", mode_name(static_cast<MacroblockCoding>(mode)), static_cast<unsigned long long>(count));
  }
  std::printf("\nwrote %s (left: decoded face; right: intra red, predicted green, skipped blue)\n",
              options.output.string().c_str());
  return 0;
}

}  // namespace svc::cli
