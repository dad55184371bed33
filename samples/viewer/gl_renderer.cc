// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/gl_renderer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include "viewer/depth_mesh.h"

namespace svc::viewer {

namespace {

// A triangle over the whole viewport; ndc is the fragment's normalised device position.
constexpr const char* kFullScreenVertex = R"(#version 330 core
out vec2 ndc;
void main() {
  ndc = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(ndc, 1.0, 1.0);
}
)";

// The cube map at infinity: each pixel looks along its ray (view.h).
constexpr const char* kSkyFragment = R"(#version 330 core
in vec2 ndc;
uniform vec3 forward;
uniform vec3 right;  // scaled by tan(fov_y / 2) * aspect
uniform vec3 up;     // scaled by tan(fov_y / 2)
uniform samplerCube cube;
out vec4 colour;
void main() { colour = vec4(texture(cube, forward + ndc.x * right + ndc.y * up).rgb, 1.0); }
)";

// Depth mesh vertices are relative to the cell's centre, so that the interpolated
// position is also the direction the centre saw the point in.
constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;  // rotation and projection: the eye at the origin
uniform vec3 centre_from_eye;
out vec3 direction;
void main() {
  direction = position;
  gl_Position = view_projection * vec4(position + centre_from_eye, 1.0);
}
)";

constexpr const char* kMeshFragment = R"(#version 330 core
in vec3 direction;
uniform samplerCube cube;
out vec4 colour;
void main() { colour = vec4(texture(cube, direction).rgb, 1.0); }
)";

constexpr const char* kTextVertex = R"(#version 330 core
uniform vec4 rect;  // left, bottom, right, top in normalised device coordinates
out vec2 uv;
void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
  uv = vec2(corner.x, 1.0 - corner.y);
  gl_Position = vec4(mix(rect.xy, rect.zw, corner), 0.0, 1.0);
}
)";

constexpr const char* kTextFragment = R"(#version 330 core
in vec2 uv;
uniform sampler2D text;
out vec4 colour;
void main() { colour = texture(text, uv); }
)";

// Near enough for a viewer standing next to a wall, far enough for the scenes' 100 m.
constexpr double kNear = 0.01, kFar = 1000.0;

Result<GLuint> compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  char log[2048] = {};
  glGetShaderInfoLog(shader, sizeof log, nullptr, log);
  glDeleteShader(shader);
  return Status(ErrorCode::kInternal, std::string("a viewer shader does not compile: ") + log);
}

Result<GLuint> link(const char* vertex_source, const char* fragment_source) {
  SVC_ASSIGN_OR_RETURN(const GLuint vertex, compile(GL_VERTEX_SHADER, vertex_source));
  auto fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
  if (!fragment.ok()) {
    glDeleteShader(vertex);
    return fragment.status();
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, *fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(*fragment);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return program;
  char log[2048] = {};
  glGetProgramInfoLog(program, sizeof log, nullptr, log);
  glDeleteProgram(program);
  return Status(ErrorCode::kInternal, std::string("the viewer's shaders do not link: ") + log);
}

void set_vec3(GLuint program, const char* name, const glm::dvec3& v) {
  glUniform3f(glGetUniformLocation(program, name), static_cast<float>(v.x), static_cast<float>(v.y),
              static_cast<float>(v.z));
}

}  // namespace

Result<std::unique_ptr<Renderer>> Renderer::create() {
  std::unique_ptr<Renderer> renderer(new Renderer());
  SVC_RETURN_IF_ERROR(renderer->build());
  return renderer;
}

Status Renderer::build() {
  SVC_ASSIGN_OR_RETURN(sky_program_, link(kFullScreenVertex, kSkyFragment));
  SVC_ASSIGN_OR_RETURN(mesh_program_, link(kMeshVertex, kMeshFragment));
  SVC_ASSIGN_OR_RETURN(text_program_, link(kTextVertex, kTextFragment));
  glGenVertexArrays(1, &empty_vao_);
  glGenVertexArrays(1, &mesh_vao_);
  glGenBuffers(1, &mesh_vbo_);
  glGenBuffers(1, &mesh_ebo_);
  glBindVertexArray(mesh_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, mesh_vbo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh_ebo_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glBindVertexArray(0);
  glGenTextures(1, &cube_);
  glBindTexture(GL_TEXTURE_CUBE_MAP, cube_);
  // Bilinear within a face and, across face edges, from the neighbouring face.
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) {
    glTexParameteri(GL_TEXTURE_CUBE_MAP, wrap, GL_CLAMP_TO_EDGE);
  }
  glGenTextures(1, &text_texture_);
  glBindTexture(GL_TEXTURE_2D, text_texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return Status::Ok();
}

Renderer::~Renderer() {
  glDeleteProgram(sky_program_);
  glDeleteProgram(mesh_program_);
  glDeleteProgram(text_program_);
  glDeleteVertexArrays(1, &empty_vao_);
  glDeleteVertexArrays(1, &mesh_vao_);
  glDeleteBuffers(1, &mesh_vbo_);
  glDeleteBuffers(1, &mesh_ebo_);
  glDeleteTextures(1, &cube_);
  glDeleteTextures(1, &text_texture_);
}

void Renderer::show_cell(const CellImages& cell, bool reproject) {
  const int size = std::max(cell.width, cell.height);
  glBindTexture(GL_TEXTURE_CUBE_MAP, cube_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (!layout_ || layout_->size() != size || !layout_->fits(cell)) layout_.emplace(cell, size);
  for (int target = 0; target < kCubeTargets; ++target) {
    const std::vector<uint8_t> texels = layout_->face(cell, target);
    glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + target, 0, GL_RGBA8, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 texels.data());
  }
  cell_centre_ = cell.centre;
  const DepthMesh mesh = reproject ? build_depth_mesh(cell) : DepthMesh{};
  glBindVertexArray(mesh_vao_);
  glBufferData(GL_ARRAY_BUFFER, mesh.positions.size() * sizeof(float), mesh.positions.data(), GL_STATIC_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.size() * sizeof(uint32_t), mesh.indices.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  mesh_indices_ = mesh.indices.size();
}

void Renderer::draw(const FrameView& view) {
  glViewport(0, 0, view.width, view.height);
  glClearColor(0, 0, 0, 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const ViewBasis basis = view_basis(view.pose);
  const double tan_half = std::tan(view.fov_y_degrees * std::numbers::pi / 360.0);
  const double aspect = static_cast<double>(view.width) / view.height;
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(sky_program_);
  set_vec3(sky_program_, "forward", basis.forward);
  set_vec3(sky_program_, "right", basis.right * (tan_half * aspect));
  set_vec3(sky_program_, "up", basis.up * tan_half);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_CUBE_MAP, cube_);
  glUniform1i(glGetUniformLocation(sky_program_, "cube"), 0);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (mesh_indices_ > 0) draw_mesh(view, basis);
  glBindVertexArray(0);
}

void Renderer::draw_mesh(const FrameView& view, const ViewBasis& basis) {
  const glm::mat4 view_projection(
      perspective(view.fov_y_degrees, static_cast<double>(view.width) / view.height, kNear, kFar) *
      view_rotation(basis));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(mesh_program_);
  glUniformMatrix4fv(glGetUniformLocation(mesh_program_, "view_projection"), 1, GL_FALSE,
                     glm::value_ptr(view_projection));
  set_vec3(mesh_program_, "centre_from_eye", cell_centre_ - view.pose.position);
  glUniform1i(glGetUniformLocation(mesh_program_, "cube"), 0);
  glBindVertexArray(mesh_vao_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh_indices_), GL_UNSIGNED_INT, nullptr);
  glDisable(GL_DEPTH_TEST);
}

void Renderer::draw_text(const TextImage& text, int width, int height) {
  if (text.width == 0 || text.height == 0) return;
  glBindTexture(GL_TEXTURE_2D, text_texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, text.width, text.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, text.rgba.data());
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glUseProgram(text_program_);
  const float right = -1.0f + 2.0f * text.width / width, bottom = 1.0f - 2.0f * text.height / height;
  glUniform4f(glGetUniformLocation(text_program_, "rect"), -1.0f, bottom, right, 1.0f);
  glUniform1i(glGetUniformLocation(text_program_, "text"), 0);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

}  // namespace svc::viewer
