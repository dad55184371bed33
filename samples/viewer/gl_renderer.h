// SPDX-License-Identifier: BSD-2-Clause
// What the viewer draws with OpenGL 3.3 core: the current cell's cube map around the
// eye, at infinity; over it, with depth, the cell's depth mesh (depth_mesh.h) seen from
// the eye's exact position, each fragment coloured by the cube map in the direction the
// cell's centre saw it; and the text overlay. Needs a current context (window.h).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>

#include "svc/status.h"
#include "viewer/cell_images.h"
#include "viewer/overlay_text.h"
#include "viewer/view.h"

namespace svc::viewer {

struct FrameView {
  Pose pose;
  double fov_y_degrees = 75;
  int width = 0, height = 0;
};

class Renderer {
 public:
  // Compiles the shaders; kInternal with the compiler's log when one fails.
  static Result<std::unique_ptr<Renderer>> create();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads the cell's cube map and, when `reproject` and the cell has depth, its mesh.
  void show_cell(const CellImages& cell, bool reproject);
  // Draws the cell into the bound framebuffer (view.width x view.height).
  void draw(const FrameView& view);
  // Draws `text` at the top left corner of a width x height framebuffer.
  void draw_text(const TextImage& text, int width, int height);

  size_t mesh_triangles() const { return mesh_indices_ / 3; }

 private:
  Renderer() = default;
  Status build();
  void draw_mesh(const FrameView& view, const ViewBasis& basis);

  unsigned sky_program_ = 0, mesh_program_ = 0, text_program_ = 0;
  unsigned empty_vao_ = 0, mesh_vao_ = 0, mesh_vbo_ = 0, mesh_ebo_ = 0;
  unsigned cube_ = 0, text_texture_ = 0;
  size_t mesh_indices_ = 0;
  std::optional<CubeMapLayout> layout_;
  glm::dvec3 cell_centre_{0, 0, 0};
};

}  // namespace svc::viewer
