// SPDX-License-Identifier: BSD-2-Clause
// Small chart renderer for the benchmark report: line charts (linear or log axes) and
// grouped bar charts drawn into an 8-bit RGB image and written as PNG.
//
// Everything is drawn by this file (antialiased lines and markers, a built-in 5x7 bitmap
// font), so plots look the same on every machine and need no font or plotting package.
// Output is deterministic: the same chart gives the same pixels.
//
// Error behaviour: drawing never fails (shapes outside the canvas are clipped; points
// that a log axis cannot show, <= 0, are dropped); write_png returns kIoError naming
// the path. Threading: a Canvas is not shared between threads; free functions are
// reentrant.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "svc/status.h"
#include "svc/types.h"

namespace svc::bench::plot {

struct Color {
  uint8_t r = 0, g = 0, b = 0;
};

// A distinct color for series `index` (a fixed palette, repeating after 10).
Color palette(size_t index);

struct Rect {
  int x = 0, y = 0, width = 0, height = 0;
};

enum class Align : uint8_t { kLeft, kCenter, kRight };

class Canvas {
 public:
  Canvas(int width, int height, Color background = {255, 255, 255});
  int width() const { return image_.width; }
  int height() const { return image_.height; }
  const ImageRGB8& image() const { return image_; }

  // Mixes `color` into pixel (x, y) with coverage alpha in [0, 1]; ignored off-canvas.
  void blend(int x, int y, Color color, double alpha);
  void fill_rect(int x0, int y0, int x1, int y1, Color color);  // [x0, x1) x [y0, y1)
  // Antialiased segment with round caps, `width` pixels wide (pixel centres at +0.5).
  void line(double x0, double y0, double x1, double y1, Color color, double width = 1.0);
  void dashed_line(double x0, double y0, double x1, double y1, Color color, double width, double dash);
  void disc(double cx, double cy, double radius, Color color);
  // Text in the built-in 5x7 font, each font pixel drawn as scale x scale pixels.
  // (x, y) is the anchor: top of the text, left/centre/right edge by `align`.
  void text(int x, int y, const std::string& text, Color color, int scale = 2, Align align = Align::kLeft);
  // Text turned 90 degrees counter-clockwise (reads bottom to top), centred on (cx, cy).
  void text_vertical(int cx, int cy, const std::string& text, Color color, int scale = 2);

 private:
  ImageRGB8 image_;
};

// Pixel size of `text` in the built-in font at `scale`.
int text_width(const std::string& text, int scale);
int text_height(int scale);

// Round tick positions covering [lo, hi]: multiples of 1, 2 or 5 x 10^k, about
// `target` of them (linear), or 1/2/5 x 10^k (log; lo > 0).
std::vector<double> linear_ticks(double lo, double hi, int target = 6);
std::vector<double> log_ticks(double lo, double hi);
// A short tick label: no trailing zeros, at most 4 significant digits.
std::string tick_label(double value);

struct Axis {
  std::string label;
  bool log = false;
  std::optional<double> min;  // unset: from the data, padded
  std::optional<double> max;
};

struct Series {
  std::string label;
  std::vector<std::pair<double, double>> points;  // (x, y), drawn in the given order
  bool dashed = false;
  std::optional<Color> color;  // unset: palette(index)
};

struct LineChart {
  std::string title;
  Axis x;
  Axis y;
  std::vector<Series> series;
};

// Axes, grid, ticks, labels, one polyline with markers per series, legend on the right.
void draw_line_chart(Canvas& canvas, Rect area, const LineChart& chart);

struct BarGroup {
  std::string label;                     // under the group
  std::vector<double> values;            // one per BarChart::series_labels entry
  std::vector<std::string> annotations;  // printed above each bar (may be empty)
};

struct BarChart {
  std::string title;
  std::string y_label;
  bool log_y = false;
  std::vector<std::string> series_labels;
  std::vector<BarGroup> groups;
};

void draw_bar_chart(Canvas& canvas, Rect area, const BarChart& chart);

// Writes the canvas as an 8-bit RGB PNG (OpenImageIO).
Status write_png(const Canvas& canvas, const std::filesystem::path& path);

}  // namespace svc::bench::plot
