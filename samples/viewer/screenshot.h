// SPDX-License-Identifier: BSD-2-Clause
// One frame rendered offscreen and written as a PNG: what --screenshot does.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "svc/status.h"
#include "viewer/gl_renderer.h"

namespace svc::viewer {

// Renders `view` (and `overlay`, when not null) into a framebuffer of its own of
// view.width x view.height and returns its pixels as RGB8, row 0 at the top.
Result<std::vector<uint8_t>> render_offscreen(Renderer* renderer, const FrameView& view, const TextImage* overlay);

// Writes the RGB8 image (row 0 at the top) to `path` as a PNG; the file appears only
// when complete.
Status write_png(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace svc::viewer
