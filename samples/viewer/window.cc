// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/window.h"

#include <epoxy/gl.h>
// epoxy declares OpenGL: GLFW is to include no GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace svc::viewer {

namespace {

// GLFW reports errors through a callback; the last one explains a failed call.
std::string& last_glfw_error() {
  static std::string message;
  return message;
}

void remember_glfw_error(int, const char* description) { last_glfw_error() = description ? description : ""; }

Status unavailable(const std::string& what) {
  const std::string reason = last_glfw_error().empty() ? "" : ": " + last_glfw_error();
  return Status(ErrorCode::kUnsupported, what + reason);
}

}  // namespace

Result<std::unique_ptr<Window>> Window::create(int width, int height, bool visible, const std::string& title) {
  glfwSetErrorCallback(remember_glfw_error);
  if (!glfwInit()) return unavailable("cannot start GLFW (no display? run under xvfb-run)");
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) {
    const Status status = unavailable("cannot create an OpenGL 3.3 core context");
    glfwTerminate();
    return status;
  }
  glfwMakeContextCurrent(window);
  return std::unique_ptr<Window>(new Window(window));
}

Window::~Window() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

std::string Window::describe_context() const {
  auto text = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return "OpenGL " + text(GL_VERSION) + ", " + text(GL_RENDERER);
}

}  // namespace svc::viewer
