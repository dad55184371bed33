// SPDX-License-Identifier: BSD-2-Clause
#include "plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include <OpenImageIO/imageio.h>

namespace svc::bench::plot {

namespace {

// The classic 5x7 font for ASCII 32..126: five column bytes per glyph, bit 0 the top row.
constexpr uint8_t kFont5x7[95][5] = {
    {0x00, 0x00, 0x00, 0x00, 0x00}, {0x00, 0x00, 0x5F, 0x00, 0x00}, {0x00, 0x07, 0x00, 0x07, 0x00},
    {0x14, 0x7F, 0x14, 0x7F, 0x14}, {0x24, 0x2A, 0x7F, 0x2A, 0x12}, {0x23, 0x13, 0x08, 0x64, 0x62},
    {0x36, 0x49, 0x55, 0x22, 0x50}, {0x00, 0x05, 0x03, 0x00, 0x00}, {0x00, 0x1C, 0x22, 0x41, 0x00},
    {0x00, 0x41, 0x22, 0x1C, 0x00}, {0x08, 0x2A, 0x1C, 0x2A, 0x08}, {0x08, 0x08, 0x3E, 0x08, 0x08},
    {0x00, 0x50, 0x30, 0x00, 0x00}, {0x08, 0x08, 0x08, 0x08, 0x08}, {0x00, 0x60, 0x60, 0x00, 0x00},
    {0x20, 0x10, 0x08, 0x04, 0x02}, {0x3E, 0x51, 0x49, 0x45, 0x3E}, {0x00, 0x42, 0x7F, 0x40, 0x00},
    {0x42, 0x61, 0x51, 0x49, 0x46}, {0x21, 0x41, 0x45, 0x4B, 0x31}, {0x18, 0x14, 0x12, 0x7F, 0x10},
    {0x27, 0x45, 0x45, 0x45, 0x39}, {0x3C, 0x4A, 0x49, 0x49, 0x30}, {0x01, 0x71, 0x09, 0x05, 0x03},
    {0x36, 0x49, 0x49, 0x49, 0x36}, {0x06, 0x49, 0x49, 0x29, 0x1E}, {0x00, 0x36, 0x36, 0x00, 0x00},
    {0x00, 0x56, 0x36, 0x00, 0x00}, {0x08, 0x14, 0x22, 0x41, 0x00}, {0x14, 0x14, 0x14, 0x14, 0x14},
    {0x00, 0x41, 0x22, 0x14, 0x08}, {0x02, 0x01, 0x51, 0x09, 0x06}, {0x32, 0x49, 0x79, 0x41, 0x3E},
    {0x7E, 0x11, 0x11, 0x11, 0x7E}, {0x7F, 0x49, 0x49, 0x49, 0x36}, {0x3E, 0x41, 0x41, 0x41, 0x22},
    {0x7F, 0x41, 0x41, 0x22, 0x1C}, {0x7F, 0x49, 0x49, 0x49, 0x41}, {0x7F, 0x09, 0x09, 0x09, 0x01},
    {0x3E, 0x41, 0x49, 0x49, 0x7A}, {0x7F, 0x08, 0x08, 0x08, 0x7F}, {0x00, 0x41, 0x7F, 0x41, 0x00},
    {0x20, 0x40, 0x41, 0x3F, 0x01}, {0x7F, 0x08, 0x14, 0x22, 0x41}, {0x7F, 0x40, 0x40, 0x40, 0x40},
    {0x7F, 0x02, 0x0C, 0x02, 0x7F}, {0x7F, 0x04, 0x08, 0x10, 0x7F}, {0x3E, 0x41, 0x41, 0x41, 0x3E},
    {0x7F, 0x09, 0x09, 0x09, 0x06}, {0x3E, 0x41, 0x51, 0x21, 0x5E}, {0x7F, 0x09, 0x19, 0x29, 0x46},
    {0x46, 0x49, 0x49, 0x49, 0x31}, {0x01, 0x01, 0x7F, 0x01, 0x01}, {0x3F, 0x40, 0x40, 0x40, 0x3F},
    {0x1F, 0x20, 0x40, 0x20, 0x1F}, {0x3F, 0x40, 0x38, 0x40, 0x3F}, {0x63, 0x14, 0x08, 0x14, 0x63},
    {0x07, 0x08, 0x70, 0x08, 0x07}, {0x61, 0x51, 0x49, 0x45, 0x43}, {0x00, 0x7F, 0x41, 0x41, 0x00},
    {0x02, 0x04, 0x08, 0x10, 0x20}, {0x00, 0x41, 0x41, 0x7F, 0x00}, {0x04, 0x02, 0x01, 0x02, 0x04},
    {0x40, 0x40, 0x40, 0x40, 0x40}, {0x00, 0x01, 0x02, 0x04, 0x00}, {0x20, 0x54, 0x54, 0x54, 0x78},
    {0x7F, 0x48, 0x44, 0x44, 0x38}, {0x38, 0x44, 0x44, 0x44, 0x20}, {0x38, 0x44, 0x44, 0x48, 0x7F},
    {0x38, 0x54, 0x54, 0x54, 0x18}, {0x08, 0x7E, 0x09, 0x01, 0x02}, {0x0C, 0x52, 0x52, 0x52, 0x3E},
    {0x7F, 0x08, 0x04, 0x04, 0x78}, {0x00, 0x44, 0x7D, 0x40, 0x00}, {0x20, 0x40, 0x44, 0x3D, 0x00},
    {0x7F, 0x10, 0x28, 0x44, 0x00}, {0x00, 0x41, 0x7F, 0x40, 0x00}, {0x7C, 0x04, 0x18, 0x04, 0x78},
    {0x7C, 0x08, 0x04, 0x04, 0x78}, {0x38, 0x44, 0x44, 0x44, 0x38}, {0x7C, 0x14, 0x14, 0x14, 0x08},
    {0x08, 0x14, 0x14, 0x18, 0x7C}, {0x7C, 0x08, 0x04, 0x04, 0x08}, {0x48, 0x54, 0x54, 0x54, 0x20},
    {0x04, 0x3F, 0x44, 0x40, 0x20}, {0x3C, 0x40, 0x40, 0x20, 0x7C}, {0x1C, 0x20, 0x40, 0x20, 0x1C},
    {0x3C, 0x40, 0x30, 0x40, 0x3C}, {0x44, 0x28, 0x10, 0x28, 0x44}, {0x0C, 0x50, 0x50, 0x50, 0x3C},
    {0x44, 0x64, 0x54, 0x4C, 0x44}, {0x00, 0x08, 0x36, 0x41, 0x00}, {0x00, 0x00, 0x7F, 0x00, 0x00},
    {0x00, 0x41, 0x36, 0x08, 0x00}, {0x08, 0x04, 0x08, 0x10, 0x08},
};

constexpr int kGlyphWidth = 5;
constexpr int kGlyphHeight = 7;
constexpr int kGlyphAdvance = 6;

const uint8_t* glyph(char c) {
  const int code = static_cast<unsigned char>(c);
  if (code < 32 || code > 126) return kFont5x7['?' - 32];
  return kFont5x7[code - 32];
}

const Color kBlack{0, 0, 0};
const Color kAxisGrey{90, 90, 90};
const Color kGridGrey{225, 225, 225};

// Maps data values to pixel positions along one axis.
struct Scale {
  double lo = 0, hi = 1;  // data range (log10 of it when log)
  double p0 = 0, p1 = 1;  // pixel positions of lo and hi
  bool log = false;
  double operator()(double v) const {
    const double t = ((log ? std::log10(v) : v) - lo) / (hi - lo);
    return p0 + t * (p1 - p0);
  }
};

std::pair<double, double> padded_range(double lo, double hi, bool log) {
  if (!(hi > lo)) {
    if (log) return {lo / 2, lo * 2};
    const double pad = std::abs(lo) > 0 ? std::abs(lo) * 0.1 : 1.0;
    return {lo - pad, hi + pad};
  }
  if (log) {
    const double ratio = std::pow(hi / lo, 0.05);
    return {lo / ratio, hi * ratio};
  }
  const double pad = (hi - lo) * 0.05;
  return {lo - pad, hi + pad};
}

}  // namespace

Color palette(size_t index) {
  static constexpr std::array<Color, 10> kColors = {{{31, 119, 180},
                                                     {214, 39, 40},
                                                     {44, 160, 44},
                                                     {255, 127, 14},
                                                     {148, 103, 189},
                                                     {140, 86, 75},
                                                     {227, 119, 194},
                                                     {127, 127, 127},
                                                     {188, 189, 34},
                                                     {23, 190, 207}}};
  return kColors[index % kColors.size()];
}

Canvas::Canvas(int width, int height, Color background) {
  image_.width = std::max(1, width);
  image_.height = std::max(1, height);
  image_.pixels.resize(static_cast<size_t>(image_.width) * image_.height * 3);
  for (size_t i = 0; i < image_.pixels.size(); i += 3) {
    image_.pixels[i] = background.r;
    image_.pixels[i + 1] = background.g;
    image_.pixels[i + 2] = background.b;
  }
}

void Canvas::blend(int x, int y, Color color, double alpha) {
  if (x < 0 || y < 0 || x >= image_.width || y >= image_.height || !(alpha > 0)) return;
  alpha = std::min(alpha, 1.0);
  uint8_t* p = &image_.pixels[(static_cast<size_t>(y) * image_.width + x) * 3];
  const uint8_t c[3] = {color.r, color.g, color.b};
  for (int k = 0; k < 3; ++k) {
    p[k] = static_cast<uint8_t>(std::lround(p[k] + (c[k] - p[k]) * alpha));
  }
}

void Canvas::fill_rect(int x0, int y0, int x1, int y1, Color color) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, image_.width);
  y1 = std::min(y1, image_.height);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) blend(x, y, color, 1.0);
  }
}

void Canvas::line(double x0, double y0, double x1, double y1, Color color, double width) {
  const double half = width / 2;
  const int bx0 = static_cast<int>(std::floor(std::min(x0, x1) - half - 1));
  const int bx1 = static_cast<int>(std::ceil(std::max(x0, x1) + half + 1));
  const int by0 = static_cast<int>(std::floor(std::min(y0, y1) - half - 1));
  const int by1 = static_cast<int>(std::ceil(std::max(y0, y1) + half + 1));
  const double dx = x1 - x0, dy = y1 - y0;
  const double length2 = dx * dx + dy * dy;
  for (int y = std::max(by0, 0); y <= std::min(by1, image_.height - 1); ++y) {
    for (int x = std::max(bx0, 0); x <= std::min(bx1, image_.width - 1); ++x) {
      const double px = x + 0.5, py = y + 0.5;
      double t = length2 > 0 ? ((px - x0) * dx + (py - y0) * dy) / length2 : 0.0;
      t = std::clamp(t, 0.0, 1.0);
      const double ex = px - (x0 + t * dx), ey = py - (y0 + t * dy);
      const double distance = std::sqrt(ex * ex + ey * ey);
      blend(x, y, color, std::clamp(half + 0.5 - distance, 0.0, 1.0));
    }
  }
}

void Canvas::dashed_line(double x0, double y0, double x1, double y1, Color color, double width, double dash) {
  const double length = std::hypot(x1 - x0, y1 - y0);
  if (length <= 0 || dash <= 0) return line(x0, y0, x1, y1, color, width);
  for (double s = 0; s < length; s += 2 * dash) {
    const double e = std::min(s + dash, length);
    line(x0 + (x1 - x0) * s / length, y0 + (y1 - y0) * s / length, x0 + (x1 - x0) * e / length,
         y0 + (y1 - y0) * e / length, color, width);
  }
}

void Canvas::disc(double cx, double cy, double radius, Color color) {
  for (int y = static_cast<int>(cy - radius - 1); y <= static_cast<int>(cy + radius + 1); ++y) {
    for (int x = static_cast<int>(cx - radius - 1); x <= static_cast<int>(cx + radius + 1); ++x) {
      const double distance = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      blend(x, y, color, std::clamp(radius + 0.5 - distance, 0.0, 1.0));
    }
  }
}

int text_width(const std::string& text, int scale) {
  return text.empty() ? 0 : (static_cast<int>(text.size()) * kGlyphAdvance - 1) * scale;
}

int text_height(int scale) { return kGlyphHeight * scale; }

void Canvas::text(int x, int y, const std::string& text, Color color, int scale, Align align) {
  const int w = text_width(text, scale);
  if (align == Align::kCenter) x -= w / 2;
  if (align == Align::kRight) x -= w;
  for (size_t i = 0; i < text.size(); ++i) {
    const uint8_t* columns = glyph(text[i]);
    const int gx = x + static_cast<int>(i) * kGlyphAdvance * scale;
    for (int col = 0; col < kGlyphWidth; ++col) {
      for (int row = 0; row < kGlyphHeight; ++row) {
        if ((columns[col] >> row) & 1) {
          fill_rect(gx + col * scale, y + row * scale, gx + (col + 1) * scale, y + (row + 1) * scale, color);
        }
      }
    }
  }
}

void Canvas::text_vertical(int cx, int cy, const std::string& text, Color color, int scale) {
  // Glyph column c, row r of character i lands at x = left + r, y = bottom - (i*advance + c).
  const int w = text_width(text, scale);
  const int left = cx - text_height(scale) / 2;
  const int bottom = cy + w / 2;
  for (size_t i = 0; i < text.size(); ++i) {
    const uint8_t* columns = glyph(text[i]);
    for (int col = 0; col < kGlyphWidth; ++col) {
      for (int row = 0; row < kGlyphHeight; ++row) {
        if (!((columns[col] >> row) & 1)) continue;
        const int along = (static_cast<int>(i) * kGlyphAdvance + col) * scale;
        fill_rect(left + row * scale, bottom - along - scale, left + (row + 1) * scale, bottom - along, color);
      }
    }
  }
}

std::vector<double> linear_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || target < 1) return ticks;
  const double raw = (hi - lo) / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  // The 1/2/5 step whose tick count comes nearest the target (ties: fewer ticks).
  double step = magnitude;
  double best_miss = std::numeric_limits<double>::infinity();
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    const double candidate = m * magnitude;
    const double count = std::floor(hi / candidate + 1e-9) - std::ceil(lo / candidate - 1e-9) + 1;
    const double miss = std::abs(count - target);
    if (miss <= best_miss) {
      best_miss = miss;
      step = candidate;
    }
  }
  for (double v = std::ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
    ticks.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return ticks;
}

std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> ticks;
  if (!(lo > 0) || !(hi > lo)) return ticks;
  const int e0 = static_cast<int>(std::floor(std::log10(lo)));
  const int e1 = static_cast<int>(std::ceil(std::log10(hi)));
  // Wide ranges: powers of ten only; narrow ones: 1, 2, 5 (and more) per decade.
  std::vector<double> mantissas = {1.0};
  if (e1 - e0 <= 3) mantissas = {1.0, 2.0, 5.0};
  if (e1 - e0 <= 1) mantissas = {1.0, 1.5, 2.0, 3.0, 5.0, 7.0};
  for (int e = e0; e <= e1; ++e) {
    for (double m : mantissas) {
      const double v = m * std::pow(10.0, e);
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) ticks.push_back(v);
    }
  }
  return ticks;
}

std::string tick_label(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return buffer;
}

void draw_line_chart(Canvas& canvas, Rect area, const LineChart& chart) {
  const int scale = 2;
  const int char_h = text_height(scale);

  // Data range over the points each axis can show.
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  auto visible = [&](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && (!chart.x.log || x > 0) && (!chart.y.log || y > 0);
  };
  for (const Series& s : chart.series) {
    for (const auto& [x, y] : s.points) {
      if (!visible(x, y)) continue;
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
  }
  if (!std::isfinite(x_lo)) {
    x_lo = chart.x.log ? 1 : 0;
    x_hi = chart.x.log ? 10 : 1;
    y_lo = chart.y.log ? 1 : 0;
    y_hi = chart.y.log ? 10 : 1;
  }
  // Explicit bounds join the data range before padding, so the data never touches a
  // padded edge; then they are applied exactly.
  auto range = [](const Axis& axis, double lo, double hi) {
    if (axis.min) lo = std::min(lo, *axis.min);
    if (axis.max) hi = std::max(hi, *axis.max);
    auto [a, b] = padded_range(lo, hi, axis.log);
    return std::pair<double, double>{axis.min.value_or(a), axis.max.value_or(b)};
  };
  auto [xr0, xr1] = range(chart.x, x_lo, x_hi);
  auto [yr0, yr1] = range(chart.y, y_lo, y_hi);

  // Legend width from the longest label.
  int legend_w = 0;
  for (const Series& s : chart.series) legend_w = std::max(legend_w, text_width(s.label, scale));
  if (legend_w > 0) legend_w += 50;

  const int left = area.x + 24 + char_h + 6 * scale * 6;  // y label + tick labels
  const int right = area.x + area.width - 16 - legend_w;
  const int top = area.y + (chart.title.empty() ? 12 : 24 + char_h);
  const int bottom = area.y + area.height - (24 + 2 * char_h);
  if (right - left < 40 || bottom - top < 40) return;

  Scale sx{chart.x.log ? std::log10(xr0) : xr0, chart.x.log ? std::log10(xr1) : xr1, double(left), double(right),
           chart.x.log};
  Scale sy{chart.y.log ? std::log10(yr0) : yr0, chart.y.log ? std::log10(yr1) : yr1, double(bottom), double(top),
           chart.y.log};

  if (!chart.title.empty())
    canvas.text((left + right) / 2, area.y + 10, chart.title, kBlack, scale, Align::kCenter);

  const auto x_ticks = chart.x.log ? log_ticks(xr0, xr1) : linear_ticks(xr0, xr1, 7);
  const auto y_ticks = chart.y.log ? log_ticks(yr0, yr1) : linear_ticks(yr0, yr1, 6);
  for (double t : x_ticks) {
    const double px = std::round(sx(t)) + 0.5;
    canvas.line(px, top, px, bottom, kGridGrey, 1);
    canvas.line(px, bottom, px, bottom + 5, kAxisGrey, 1);
    canvas.text(static_cast<int>(px), bottom + 9, tick_label(t), kBlack, scale, Align::kCenter);
  }
  for (double t : y_ticks) {
    const double py = std::round(sy(t)) + 0.5;
    canvas.line(left, py, right, py, kGridGrey, 1);
    canvas.line(left - 5, py, left, py, kAxisGrey, 1);
    canvas.text(left - 9, static_cast<int>(py) - char_h / 2, tick_label(t), kBlack, scale, Align::kRight);
  }
  canvas.line(left + 0.5, top, left + 0.5, bottom + 0.5, kAxisGrey, 1);
  canvas.line(left, bottom + 0.5, right, bottom + 0.5, kAxisGrey, 1);
  canvas.text((left + right) / 2, bottom + 15 + char_h, chart.x.label + (chart.x.log ? " (log)" : ""), kBlack,
              scale, Align::kCenter);
  canvas.text_vertical(area.x + 8 + char_h / 2, (top + bottom) / 2, chart.y.label + (chart.y.log ? " (log)" : ""),
                       kBlack, scale);

  // Series, clipped to the plot box by dropping segments that leave it.
  auto inside = [&](double px, double py) {
    return px >= left - 1 && px <= right + 1 && py >= top - 1 && py <= bottom + 1;
  };
  for (size_t i = 0; i < chart.series.size(); ++i) {
    const Series& s = chart.series[i];
    const Color color = s.color.value_or(palette(i));
    bool have_prev = false;
    double prev_x = 0, prev_y = 0;
    for (const auto& [x, y] : s.points) {
      if (!visible(x, y)) {
        have_prev = false;
        continue;
      }
      const double px = sx(x), py = sy(y);
      if (!inside(px, py)) {
        have_prev = false;
        continue;
      }
      if (have_prev) {
        if (s.dashed) {
          canvas.dashed_line(prev_x, prev_y, px, py, color, 2.0, 7.0);
        } else {
          canvas.line(prev_x, prev_y, px, py, color, 2.0);
        }
      }
      canvas.disc(px, py, 4.0, color);
      prev_x = px;
      prev_y = py;
      have_prev = true;
    }
  }

  // Legend on the right of the plot box.
  int ly = top + 4;
  for (size_t i = 0; i < chart.series.size(); ++i) {
    const Series& s = chart.series[i];
    const Color color = s.color.value_or(palette(i));
    const int lx = right + 16;
    if (s.dashed) {
      canvas.dashed_line(lx, ly + char_h / 2.0, lx + 28, ly + char_h / 2.0, color, 2.0, 5.0);
    } else {
      canvas.line(lx, ly + char_h / 2.0, lx + 28, ly + char_h / 2.0, color, 2.0);
    }
    canvas.disc(lx + 14, ly + char_h / 2.0, 4.0, color);
    canvas.text(lx + 36, ly, s.label, kBlack, scale);
    ly += char_h + 10;
  }
}

void draw_bar_chart(Canvas& canvas, Rect area, const BarChart& chart) {
  const int scale = 2;
  const int char_h = text_height(scale);
  double v_lo = std::numeric_limits<double>::infinity(), v_hi = 0;
  for (const BarGroup& g : chart.groups) {
    for (double v : g.values) {
      if (!std::isfinite(v) || v <= 0) continue;
      v_lo = std::min(v_lo, v);
      v_hi = std::max(v_hi, v);
    }
  }
  if (!std::isfinite(v_lo)) {
    v_lo = 1;
    v_hi = 10;
  }
  double y0 = 0, y1 = v_hi * 1.15;
  if (chart.log_y) {
    y0 = std::pow(10.0, std::floor(std::log10(v_lo)));
    y1 = std::pow(10.0, std::log10(v_hi) + 0.25);
  }

  int legend_w = 0;
  for (const auto& label : chart.series_labels) legend_w = std::max(legend_w, text_width(label, scale));
  if (legend_w > 0) legend_w += 56;
  const int left = area.x + 24 + char_h + 6 * scale * 6;
  const int right = area.x + area.width - 16 - legend_w;
  const int top = area.y + (chart.title.empty() ? 12 : 24 + char_h);
  const int bottom = area.y + area.height - (24 + 2 * char_h);
  if (right - left < 40 || bottom - top < 40 || chart.groups.empty()) return;
  Scale sy{chart.log_y ? std::log10(y0) : y0, chart.log_y ? std::log10(y1) : y1, double(bottom), double(top),
           chart.log_y};

  if (!chart.title.empty())
    canvas.text((left + right) / 2, area.y + 10, chart.title, kBlack, scale, Align::kCenter);
  const auto ticks = chart.log_y ? log_ticks(y0, y1) : linear_ticks(y0, y1, 6);
  for (double t : ticks) {
    const double py = std::round(sy(t)) + 0.5;
    canvas.line(left, py, right, py, kGridGrey, 1);
    canvas.line(left - 5, py, left, py, kAxisGrey, 1);
    canvas.text(left - 9, static_cast<int>(py) - char_h / 2, tick_label(t), kBlack, scale, Align::kRight);
  }
  canvas.text_vertical(area.x + 8 + char_h / 2, (top + bottom) / 2, chart.y_label + (chart.log_y ? " (log)" : ""),
                       kBlack, scale);

  const double group_w = static_cast<double>(right - left) / chart.groups.size();
  const size_t per_group = std::max<size_t>(1, chart.series_labels.size());
  const double bar_w = group_w * 0.8 / per_group;
  for (size_t g = 0; g < chart.groups.size(); ++g) {
    const BarGroup& group = chart.groups[g];
    const double gx = left + g * group_w + group_w * 0.1;
    for (size_t b = 0; b < group.values.size() && b < per_group; ++b) {
      const double v = group.values[b];
      if (!std::isfinite(v) || v <= 0) continue;
      const int x0 = static_cast<int>(std::round(gx + b * bar_w));
      const int x1 = static_cast<int>(std::round(gx + (b + 1) * bar_w)) - 2;
      const int yv = static_cast<int>(std::round(std::clamp(sy(v), double(top), double(bottom))));
      canvas.fill_rect(x0, yv, x1, bottom, palette(b));
      if (b < group.annotations.size() && !group.annotations[b].empty()) {
        canvas.text((x0 + x1) / 2, yv - char_h / 2 - 6, group.annotations[b], kBlack, 1, Align::kCenter);
      }
    }
    canvas.text(static_cast<int>(left + (g + 0.5) * group_w), bottom + 9, group.label, kBlack, scale,
                Align::kCenter);
  }
  canvas.line(left + 0.5, top, left + 0.5, bottom + 0.5, kAxisGrey, 1);
  canvas.line(left, bottom + 0.5, right, bottom + 0.5, kAxisGrey, 1);

  int ly = top + 4;
  for (size_t i = 0; i < chart.series_labels.size(); ++i) {
    const int lx = right + 16;
    canvas.fill_rect(lx, ly, lx + 18, ly + char_h, palette(i));
    canvas.text(lx + 26, ly, chart.series_labels[i], kBlack, scale);
    ly += char_h + 10;
  }
}

Status write_png(const Canvas& canvas, const std::filesystem::path& path) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) return Status(ErrorCode::kIoError, "cannot create PNG writer for " + path.string());
  const ImageRGB8& image = canvas.image();
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data()) ||
      !out->close()) {
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

}  // namespace svc::bench::plot
