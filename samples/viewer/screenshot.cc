// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/screenshot.h"

#include <string>
#include <system_error>

#include <OpenImageIO/imageio.h>
#include <epoxy/gl.h>
#include <unistd.h>

namespace svc::viewer {

namespace {

// A framebuffer object with colour and depth renderbuffers, deleted with it.
class Framebuffer {
 public:
  Framebuffer(int width, int height) {
    glGenFramebuffers(1, &framebuffer_);
    glGenRenderbuffers(2, renderbuffers_);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffers_[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, renderbuffers_[1]);
  }
  ~Framebuffer() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteRenderbuffers(2, renderbuffers_);
    glDeleteFramebuffers(1, &framebuffer_);
  }
  bool complete() const { return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }

 private:
  GLuint framebuffer_ = 0;
  GLuint renderbuffers_[2] = {0, 0};
};

}  // namespace

Result<std::vector<uint8_t>> render_offscreen(Renderer* renderer, const FrameView& view, const TextImage* overlay) {
  Framebuffer framebuffer(view.width, view.height);
  if (!framebuffer.complete()) {
    return Status(ErrorCode::kUnsupported, "cannot render offscreen at " + std::to_string(view.width) + "x" +
                                               std::to_string(view.height) + " (framebuffer incomplete)");
  }
  renderer->draw(view);
  if (overlay) renderer->draw_text(*overlay, view.width, view.height);
  const size_t row = static_cast<size_t>(view.width) * 3;
  std::vector<uint8_t> bottom_up(row * view.height), rgb(row * view.height);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, view.width, view.height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  if (glGetError() != GL_NO_ERROR) return Status(ErrorCode::kInternal, "reading the rendered frame back failed");
  // OpenGL's rows start at the bottom, images' at the top.
  for (int y = 0; y < view.height; ++y) {
    std::copy_n(bottom_up.begin() + (view.height - 1 - y) * row, row, rgb.begin() + y * row);
  }
  return rgb;
}

Status write_png(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  // Written beside the output and renamed: a failed or interrupted write leaves nothing.
  std::filesystem::path staged = path;
  staged += ".tmp-" + std::to_string(getpid()) + ".png";
  auto out = OIIO::ImageOutput::create(staged.string());
  if (!out) return Status(ErrorCode::kIoError, "no PNG writer for " + path.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(staged.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !out->close()) {
    std::error_code ignored;
    std::filesystem::remove(staged, ignored);
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  std::error_code ec;
  std::filesystem::rename(staged, path, ec);
  if (ec) {
    std::filesystem::remove(staged, ec);
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + ec.message());
  }
  return Status::Ok();
}

}  // namespace svc::viewer
