// SPDX-License-Identifier: BSD-2-Clause
// A GLFW window with an OpenGL 3.3 core context, current on the calling thread; hidden
// for offscreen rendering. GLFW is initialised with the first window and terminated
// with the last.
#pragma once

#include <memory>
#include <string>

#include "svc/status.h"

struct GLFWwindow;

namespace svc::viewer {

class Window {
 public:
  // kUnsupported, with GLFW's reason, when no display or no OpenGL 3.3 core context is
  // available.
  static Result<std::unique_ptr<Window>> create(int width, int height, bool visible, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* handle() const { return window_; }
  // "OpenGL 3.3 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string describe_context() const;

 private:
  explicit Window(GLFWwindow* window) : window_(window) {}
  GLFWwindow* window_ = nullptr;
};

}  // namespace svc::viewer
