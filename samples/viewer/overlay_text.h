// SPDX-License-Identifier: BSD-2-Clause
// Lines of text drawn into an RGBA image with a built-in 5x7 pixel font (capitals,
// digits and some punctuation; lower case is drawn as capitals): the viewer's on-screen
// figures, with no font file to find.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace svc::viewer {

struct TextImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // row 0 at the top; white text on a translucent dark box
};

// `scale` pixels a font pixel. Characters the font lacks are drawn as '?'.
TextImage render_text(const std::vector<std::string>& lines, int scale);

}  // namespace svc::viewer
