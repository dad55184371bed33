// SPDX-License-Identifier: BSD-2-Clause
// svc inspect: a decoded face beside its macroblock classification, as in the
// dissertation's Figure 4.5, with a legend naming each color, at a readable scale.
#include <algorithm>
#include <cstdio>
#include <map>
#include <string_view>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/output_paths.h"
#include "svc/reader.h"

namespace svc::cli {

using command_line::check_output;
using command_line::OutputKind;

namespace {

constexpr MacroblockCoding kModes[] = {MacroblockCoding::kIntra, MacroblockCoding::kForward,
                                       MacroblockCoding::kBackward, MacroblockCoding::kBidirectional,
                                       MacroblockCoding::kSkipped};

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

// Colors far apart in hue and lightness, so that each mode reads at a glance.
std::array<uint8_t, 3> mode_color(MacroblockCoding mode) {
  switch (mode) {
    case MacroblockCoding::kIntra: return {220, 40, 40};           // red
    case MacroblockCoding::kForward: return {40, 190, 60};         // green
    case MacroblockCoding::kBackward: return {240, 200, 30};       // yellow
    case MacroblockCoding::kBidirectional: return {170, 60, 220};  // purple
    case MacroblockCoding::kSkipped: return {40, 110, 240};        // blue
  }
  return {128, 128, 128};
}

// Warped macroblocks (any direction) take a color of their own.
constexpr std::array<uint8_t, 3> kWarpedColor = {30, 200, 200};  // cyan

// 3x5 glyphs of the letters the legend uses, one row per 3 bits (top row first).
uint16_t glyph(char c) {
  switch (c) {
    case 'a': return 0b010101111101101;
    case 'b': return 0b110101110101110;
    case 'c': return 0b011100100100011;
    case 'd': return 0b110101101101110;
    case 'e': return 0b111100110100111;
    case 'f': return 0b111100110100100;
    case 'i': return 0b111010010010111;
    case 'k': return 0b101101110101101;
    case 'l': return 0b100100100100111;
    case 'n': return 0b101111111111101;
    case 'o': return 0b010101101101010;
    case 'p': return 0b110101110100100;
    case 'r': return 0b110101110101101;
    case 's': return 0b011100010001110;
    case 't': return 0b111010010010010;
    case 'w': return 0b101101111111101;
    default: return 0;
  }
}

class Sheet {
 public:
  Sheet(int width, int height) {
    image_.width = width;
    image_.height = height;
    image_.pixels.assign(static_cast<size_t>(width) * height * 3, 255);
  }
  void fill(int x0, int y0, int w, int h, const std::array<uint8_t, 3>& color) {
    for (int y = std::max(0, y0); y < std::min(image_.height, y0 + h); ++y) {
      for (int x = std::max(0, x0); x < std::min(image_.width, x0 + w); ++x) set(x, y, color);
    }
  }
  void set(int x, int y, const std::array<uint8_t, 3>& color) {
    uint8_t* p = &image_.pixels[(static_cast<size_t>(y) * image_.width + x) * 3];
    p[0] = color[0], p[1] = color[1], p[2] = color[2];
  }
  // Text in the 3x5 glyphs, each glyph pixel `unit` wide.
  void text(int x, int y, std::string_view s, int unit) {
    for (char c : s) {
      const uint16_t bits = glyph(c);
      for (int row = 0; row < 5; ++row) {
        for (int col = 0; col < 3; ++col) {
          if (bits >> (14 - row * 3 - col) & 1) fill(x + col * unit, y + row * unit, unit, unit, {20, 20, 20});
        }
      }
      x += 4 * unit;
    }
  }
  const ImageRGB8& image() const { return image_; }

 private:
  ImageRGB8 image_;
};

// Left: the decoded face. Right: the same face dimmed and tinted by macroblock mode,
// macroblock edges drawn. Below: one swatch and name per mode.
ImageRGB8 draw_sheet(const InspectedFace& inspected, int scale) {
  const ImageRGB8& face = inspected.image;
  const int w = face.width * scale, h = face.height * scale, gap = 8;
  const int unit = std::max(2, h / 160), line = 8 * unit;
  Sheet sheet(2 * w + gap, h + gap + line * static_cast<int>(std::size(kModes) + 1));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int fx = x / scale, fy = y / scale;
      const uint8_t* src = &face.pixels[(static_cast<size_t>(fy) * face.width + fx) * 3];
      const size_t mb = static_cast<size_t>(fy / 16) * inspected.macroblocks_x + fx / 16;
      const bool warped = mb < inspected.warped.size() && inspected.warped[mb] != 0;
      const auto color = warped ? kWarpedColor : mode_color(inspected.modes[mb]);
      // Partition edges are drawn at 8 like macroblock edges at 16.
      const MacroblockPartition partition = mb < inspected.partitions.size() ? inspected.partitions[mb]
                                                                             : MacroblockPartition::k16x16;
      const int cell_x = partition == MacroblockPartition::k8x16 || partition == MacroblockPartition::k8x8 ? 8 : 16;
      const int cell_y = partition == MacroblockPartition::k16x8 || partition == MacroblockPartition::k8x8 ? 8 : 16;
      const bool edge = (x % (cell_x * scale)) < std::max(1, scale / 2) ||
                        (y % (cell_y * scale)) < std::max(1, scale / 2);
      std::array<uint8_t, 3> tinted;
      for (int c = 0; c < 3; ++c)
        tinted[c] = edge ? color[c] : static_cast<uint8_t>((src[c] * 2 + color[c] * 3) / 5);
      sheet.set(x, y, {src[0], src[1], src[2]});
      sheet.set(w + gap + x, y, tinted);
    }
  }
  int y = h + gap;
  for (MacroblockCoding mode : kModes) {
    sheet.fill(0, y, 6 * unit, 6 * unit, mode_color(mode));
    sheet.text(8 * unit, y + unit / 2, mode_name(mode), unit);
    y += line;
  }
  sheet.fill(0, y, 6 * unit, 6 * unit, kWarpedColor);
  sheet.text(8 * unit, y + unit / 2, "warped", unit);
  return sheet.image();
}

}  // namespace

int inspect_command(const InspectOptions& options) {
  const Status writable = check_output(options.output, OutputKind::kFile, options.overwrite, {options.input});
  if (!writable.ok()) return report_error(writable);
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  auto inspected = (*reader)->inspect_face(options.cell, options.face);
  if (!inspected.ok()) return report_error(inspected.status());
  const int scale = options.scale > 0 ? options.scale
                                      : std::max(1, (512 + inspected->image.height - 1) / inspected->image.height);
  Status status = write_png(options.output, draw_sheet(*inspected, scale));
  if (!status.ok()) return report_error(status);
  std::map<MacroblockCoding, uint64_t> counts;
  for (MacroblockCoding m : inspected->modes) counts[m] += 1;
  const auto warped = static_cast<uint64_t>(std::count(inspected->warped.begin(), inspected->warped.end(), 1));
  if (options.verbosity.json) {
    json modes = json::object();
    for (MacroblockCoding mode : kModes) modes[mode_name(mode)] = counts[mode];
    modes["warped"] = warped;  // also counted under their direction
    print_json({{"command", "inspect"},
                {"input", options.input.string()},
                {"output", options.output.string()},
                {"cell", {options.cell.x, options.cell.y, options.cell.z}},
                {"face", face_name(options.face)},
                {"type", inspected->type == FaceType::kIntra ? "intra" : "predicted"},
                {"scale", scale},
                {"macroblocks", modes}});
    return 0;
  }
  if (!options.verbosity.show_summary()) return 0;
  std::printf("%s: %s-face, %zu macroblocks:", face_label(options.cell, options.face).c_str(),
              inspected->type == FaceType::kIntra ? "I" : "B", inspected->modes.size());
  for (const auto& [mode, count] : counts)
    std::printf(" %s %llu", mode_name(mode), static_cast<unsigned long long>(count));
  std::printf(" (warped %llu of them)", static_cast<unsigned long long>(warped));
  std::printf(
      "\nwrote %s at %dx (left: decoded face; right: intra red, forward green, backward yellow, "
      "bidirectional purple, skipped blue, warped cyan; legend below)\n",
      options.output.string().c_str(), scale);
  return 0;
}

}  // namespace svc::cli
