// SPDX-License-Identifier: BSD-2-Clause
// svc-viewer: walks through an .svc database. The current cell's cube map is drawn
// around the eye; where the file holds depth, the cell's faces are reprojected to the
// eye's exact position between cells. The reader's prefetch follows the eye, and an
// overlay shows decode latency, cache hits and misses and frame time.
//
//   svc-viewer FILE.svc [--path FILE [--speed CELLS_PER_S]] [--at X,Y,Z] [--look YAW,PITCH]
//                       [--size WxH] [--fov DEG] [--no-reprojection | --reprojection]
//                       [--frames N]
//   svc-viewer FILE.svc --screenshot OUT.png --at X,Y,Z --look YAW,PITCH [--size WxH]
//                       [--fov DEG] [--no-reprojection | --reprojection] [--overlay] [-y]
//   svc-viewer FILE.svc --views FILE [--size WxH] [--fov DEG] [--no-reprojection |
//                       --reprojection] [--overlay] [-y]
//   svc-viewer --gl-info
//
// Keys: W A S D move, Q E down and up, Shift faster, mouse with the left button held
// looks around, R toggles reprojection, O the overlay, Escape quits.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <epoxy/gl.h>
// epoxy declares OpenGL: GLFW is to include no GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/output_paths.h"
#include "command_line/report.h"
#include "viewer/cell_loader.h"
#include "viewer/gl_renderer.h"
#include "viewer/navigation.h"
#include "viewer/screenshot.h"
#include "viewer/window.h"
#include "walkthrough/replay.h"

namespace {

using namespace svc::viewer;
constexpr const char* kProgram = "svc-viewer";

struct Options {
  std::string input, screenshot, views, path;
  std::string at, look = "0,0", size = "640x480";
  double fov = 75, speed = 1;
  bool no_reprojection = false, reprojection = false, overlay = false, overwrite = false, gl_info = false;
  int frames = 0;
  // Parsed from the strings above.
  std::optional<glm::dvec3> position;
  double yaw = 0, pitch = 0;
  int width = 640, height = 480;
};

// "a,b,c" with `count` finite numbers.
bool parse_numbers(const std::string& text, size_t count, char separator, std::vector<double>* out) {
  out->clear();
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, separator)) {
    std::stringstream item_stream(item);
    double value;
    if (!(item_stream >> value) || !(item_stream >> std::ws).eof() || !std::isfinite(value)) return false;
    out->push_back(value);
  }
  return out->size() == count;
}

// Checks and converts --at, --look and --size; a message naming the option otherwise.
std::optional<std::string> parse_view_options(Options* o) {
  std::vector<double> v;
  if (!o->at.empty()) {
    if (!parse_numbers(o->at, 3, ',', &v)) return "--at wants X,Y,Z, got \"" + o->at + "\"";
    o->position = glm::dvec3(v[0], v[1], v[2]);
  }
  if (!parse_numbers(o->look, 2, ',', &v)) return "--look wants YAW,PITCH in degrees, got \"" + o->look + "\"";
  o->yaw = v[0];
  o->pitch = v[1];
  if (!parse_numbers(o->size, 2, 'x', &v) || v[0] < 16 || v[1] < 16 || v[0] > 8192 || v[1] > 8192 ||
      v[0] != std::floor(v[0]) || v[1] != std::floor(v[1])) {
    return "--size wants WxH, whole numbers of pixels in 16..8192, got \"" + o->size + "\"";
  }
  o->width = static_cast<int>(v[0]);
  o->height = static_cast<int>(v[1]);
  if (!o->gl_info && o->input.empty()) return "an .svc file is needed (or --gl-info)";
  if ((!o->screenshot.empty() || !o->views.empty()) && !o->path.empty()) {
    return "--screenshot and --views render still frames: --path does not go with them";
  }
  return std::nullopt;
}

void add_options(CLI::App* app, Options* o) {
  app->add_option("input", o->input, "the .svc file")->check(CLI::ExistingFile);
  auto* screenshot =
      app->add_option("--screenshot", o->screenshot, "render one frame offscreen into this PNG and exit")
          ->check(svc::command_line::not_standard_output());
  app->add_option("--views", o->views,
                  "render one frame offscreen for each line \"X,Y,Z YAW,PITCH OUT.png\" of this file ('#' starts a "
                  "comment) and exit")
      ->check(CLI::ExistingFile)
      ->excludes(screenshot);
  app->add_option("--at", o->at, "eye position X,Y,Z in world units (default: the middle cell's centre)");
  app->add_option("--look", o->look, "view direction YAW,PITCH in degrees: 0,0 looks along -z, yaw 90 along -x")
      ->capture_default_str();
  app->add_option("--size", o->size, "window or screenshot size WxH in pixels")->capture_default_str();
  app->add_option("--fov", o->fov, "vertical field of view in degrees")
      ->check(CLI::Range(10.0, 150.0))
      ->capture_default_str();
  app->add_option("--path", o->path,
                  "walk these waypoints (\"x y z\" a line, as svc-walkthrough reads them), then exit")
      ->check(CLI::ExistingFile);
  app->add_option("--speed", o->speed, "walking speed in cells per second")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  auto* off = app->add_flag("--no-reprojection", o->no_reprojection,
                            "draw the cell's cube map at infinity even where the file holds depth");
  app->add_flag("--reprojection", o->reprojection,
                "reproject the cell's faces with their depth to the eye (the default where the file holds "
                "depth); an error for a file without depth")
      ->excludes(off);
  app->add_flag("--overlay", o->overlay, "draw the figures overlay into the screenshot too");
  app->add_option("--frames", o->frames, "stop after this many frames (0: run until closed)")
      ->check(svc::command_line::integer_in(0, 100000000));
  app->add_flag("--gl-info", o->gl_info, "print the OpenGL version and renderer the viewer gets, and exit");
  svc::command_line::add_overwrite_flag(app, &o->overwrite);
}

// The centre of the grid's middle cell, or of the first cell when that one is absent.
glm::dvec3 default_position(const CellLoader& loader) {
  const svc::FileInfo& info = loader.info();
  glm::dvec3 middle;
  for (int a = 0; a < 3; ++a) middle[a] = info.grid_origin[a] + (info.grid_dims[a] / 2) * info.grid_spacing[a];
  return loader.cell_centre(loader.cell_for(middle));
}

// Whether frames reproject with depth; an error when --reprojection asks for depth the
// file does not hold.
svc::Result<bool> choose_reprojection(const Options& o, const CellLoader& loader) {
  if (o.reprojection && !loader.file_has_depth()) {
    return svc::Status(svc::ErrorCode::kInvalidArgument,
                       o.input + " holds no depth (encode with svc encode --depth); --reprojection needs it");
  }
  return !o.no_reprojection && loader.file_has_depth();
}

std::string format(const char* pattern, auto... values) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

std::vector<std::string> overlay_lines(const CellLoader& loader, const CellImages& cell, const Renderer& renderer,
                                       bool reproject, double frame_ms) {
  const svc::ReaderStats stats = loader.stats();
  return {
      format("CELL %d,%d,%d  %s", cell.cell.x, cell.cell.y, cell.cell.z,
             reproject ? format("REPROJECTED, %zu TRIANGLES", renderer.mesh_triangles()).c_str()
                       : "CUBE MAP AT INFINITY"),
      format("DECODE LAST %.1f MS  P99 %.1f MS  (%d CELLS)", loader.last_latency_ms(),
             loader.latency_percentile_ms(0.99), loader.loads()),
      format("FACE CACHE %llu HITS %llu MISSES  PREFETCHED %llu",
             static_cast<unsigned long long>(stats.face_cache.hits),
             static_cast<unsigned long long>(stats.face_cache.misses),
             static_cast<unsigned long long>(stats.prefetch_faces)),
      format("FRAME %.1f MS", frame_ms),
  };
}

// One frame to render offscreen.
struct Shot {
  glm::dvec3 at{0, 0, 0};
  double yaw = 0, pitch = 0;
  std::string output;
};

// The lines "X,Y,Z YAW,PITCH OUT.png" of a --views file ('#' starts a comment).
svc::Result<std::vector<Shot>> read_views(const std::string& path) {
  std::ifstream in(path);
  if (!in) return svc::Status(svc::ErrorCode::kNotFound, "cannot open views file " + path);
  std::vector<Shot> shots;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string at, look, output, extra;
    if (!(fields >> at)) continue;  // blank
    std::vector<double> p, l;
    if (!(fields >> look >> output) || (fields >> extra) || !parse_numbers(at, 3, ',', &p) ||
        !parse_numbers(look, 2, ',', &l)) {
      return svc::Status(svc::ErrorCode::kInvalidArgument,
                         path + ":" + std::to_string(number) + ": expected \"X,Y,Z YAW,PITCH OUT.png\"");
    }
    shots.push_back(Shot{{p[0], p[1], p[2]}, l[0], l[1], output});
  }
  if (shots.empty()) return svc::Status(svc::ErrorCode::kInvalidArgument, path + ": no views");
  return shots;
}

// Renders one shot of the cell shown and writes it.
svc::Status render_shot(const Options& o, const Shot& shot, const CellLoader& loader, const CellImages& cell,
                        Renderer* renderer, bool reproject) {
  const FrameView view{Pose{shot.at, shot.yaw, shot.pitch}, o.fov, o.width, o.height};
  const auto start = std::chrono::steady_clock::now();
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> rgb, render_offscreen(renderer, view, nullptr));
  if (o.overlay) {
    // The overlay's frame time is that of the frame without it, read back.
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const TextImage text = render_text(overlay_lines(loader, cell, *renderer, reproject, ms), 1);
    SVC_ASSIGN_OR_RETURN(rgb, render_offscreen(renderer, view, &text));
  }
  SVC_RETURN_IF_ERROR(write_png(shot.output, o.width, o.height, rgb));
  std::printf("%s: wrote %s (%dx%d) from %s, %s\n", kProgram, shot.output.c_str(), o.width, o.height,
              svc::cell_label(cell.cell).c_str(),
              reproject ? format("reprojected with depth (%zu triangles)", renderer->mesh_triangles()).c_str()
                        : "cube map at infinity");
  return svc::Status::Ok();
}

// Renders the shots in order, decoding a cell when a shot's eye lies in another one.
int screenshots(const Options& o, CellLoader* loader, const std::vector<Shot>& shots) {
  auto reproject = choose_reprojection(o, *loader);
  if (!reproject.ok()) return svc::command_line::report_failure(kProgram, reproject.status());
  auto window = Window::create(64, 64, false, kProgram);
  if (!window.ok()) return svc::command_line::report_failure(kProgram, window.status());
  auto renderer = Renderer::create();
  if (!renderer.ok()) return svc::command_line::report_failure(kProgram, renderer.status());
  CellImages cell;
  bool shown = false;
  for (const Shot& shot : shots) {
    const svc::CellIndex index = loader->cell_for(shot.at);
    if (!shown || !(index == cell.cell)) {
      const svc::Status loaded = loader->load(index, &cell);
      if (!loaded.ok()) return svc::command_line::report_failure(kProgram, loaded);
      (*renderer)->show_cell(cell, *reproject);
      shown = true;
    }
    const svc::Status status = render_shot(o, shot, *loader, cell, renderer->get(), *reproject);
    if (!status.ok()) return svc::command_line::report_failure(kProgram, status);
    if (svc::command_line::interrupted()) {  // nothing is left behind
      std::error_code ignored;
      for (const Shot& written : shots) std::filesystem::remove(written.output, ignored);
      return svc::command_line::report_failure(kProgram, svc::Status::Ok());
    }
  }
  return 0;
}

// Keys held and mouse motion (while the left button is down) since the last frame.
FlyInput read_input(GLFWwindow* window, glm::dvec2* last_cursor) {
  auto held = [&](int key) { return glfwGetKey(window, key) == GLFW_PRESS ? 1.0 : 0.0; };
  FlyInput in;
  in.forward = held(GLFW_KEY_W) - held(GLFW_KEY_S);
  in.right = held(GLFW_KEY_D) - held(GLFW_KEY_A);
  in.up = held(GLFW_KEY_E) - held(GLFW_KEY_Q);
  glm::dvec2 cursor;
  glfwGetCursorPos(window, &cursor.x, &cursor.y);
  if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
    in.mouse_dx = cursor.x - last_cursor->x;
    in.mouse_dy = cursor.y - last_cursor->y;
  }
  *last_cursor = cursor;
  return in;
}

// Keys that toggle once per press.
struct Toggles {
  bool reproject = false, overlay = true;
  bool r_down = false, o_down = false;
  // True when reprojection changed.
  bool update(GLFWwindow* window, bool depth) {
    const bool r = glfwGetKey(window, GLFW_KEY_R) == GLFW_PRESS, o = glfwGetKey(window, GLFW_KEY_O) == GLFW_PRESS;
    const bool changed = r && !r_down && depth;
    if (changed) reproject = !reproject;
    if (o && !o_down) overlay = !overlay;
    r_down = r;
    o_down = o;
    return changed;
  }
};

struct WalkState {
  Pose pose;
  std::optional<PathWalk> walk;
  glm::dvec2 cursor{0, 0};
  double speed = 1;  // world units per second
};

// Advances the eye by one frame; false when a walked path is over.
bool advance(GLFWwindow* window, double elapsed, double dt, WalkState* s, glm::dvec3* velocity) {
  if (s->walk) {
    const PathWalk::Sample sample = s->walk->at(elapsed);
    s->pose.position = sample.position;
    *velocity = sample.velocity;
    if (glm::length(sample.velocity) > 0) look_along(sample.velocity, &s->pose);
    return !sample.finished;
  }
  const bool fast = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
  *velocity = fly(read_input(window, &s->cursor), dt, s->speed * (fast ? 4 : 1), 0.2, &s->pose);
  return true;
}

struct WalkSummary {
  int frames = 0;
  double seconds = 0;
};

void print_summary(const CellLoader& loader, const WalkSummary& w) {
  const svc::ReaderStats stats = loader.stats();
  std::printf(
      "%s: %d frames in %.2f s (%.1f ms a frame), %d cells shown; decode latency p50 %.2f ms, p99 %.2f ms; face "
      "cache %llu hits, %llu misses; %llu faces prefetched\n",
      kProgram, w.frames, w.seconds, w.frames ? 1000 * w.seconds / w.frames : 0.0, loader.loads(),
      loader.latency_percentile_ms(0.5), loader.latency_percentile_ms(0.99),
      static_cast<unsigned long long>(stats.face_cache.hits),
      static_cast<unsigned long long>(stats.face_cache.misses),
      static_cast<unsigned long long>(stats.prefetch_faces));
}

svc::Status walk_loop(const Options& o, CellLoader* loader, Window* window, Renderer* renderer, WalkState* s) {
  Toggles toggles;
  toggles.reproject = !o.no_reprojection && loader->file_has_depth();
  CellImages cell;
  bool shown = false;
  WalkSummary summary;
  double frame_ms = 0;
  const double start = glfwGetTime();
  double last = start;
  while (!glfwWindowShouldClose(window->handle()) && glfwGetKey(window->handle(), GLFW_KEY_ESCAPE) != GLFW_PRESS &&
         !svc::command_line::interrupted()) {
    const double now = glfwGetTime(), dt = now - last;
    last = now;
    frame_ms = frame_ms == 0 ? 1000 * dt : 0.9 * frame_ms + 100 * dt;  // smoothed: readable on screen
    glm::dvec3 velocity(0.0);
    if (!advance(window->handle(), now - start, dt, s, &velocity)) break;
    SVC_RETURN_IF_ERROR(loader->follow(s->pose.position, velocity));
    const bool toggled = toggles.update(window->handle(), loader->file_has_depth());
    const svc::CellIndex index = loader->cell_for(s->pose.position);
    if (!shown || !(index == cell.cell)) {
      SVC_RETURN_IF_ERROR(loader->load(index, &cell));
      shown = false;
    }
    if (!shown || toggled) renderer->show_cell(cell, toggles.reproject);
    shown = true;
    FrameView view{s->pose, o.fov, 0, 0};
    glfwGetFramebufferSize(window->handle(), &view.width, &view.height);
    if (view.width > 0 && view.height > 0) {
      renderer->draw(view);
      if (toggles.overlay) {
        renderer->draw_text(render_text(overlay_lines(*loader, cell, *renderer, toggles.reproject, frame_ms), 2),
                            view.width, view.height);
      }
    }
    glfwSwapBuffers(window->handle());
    glfwPollEvents();
    if (++summary.frames == o.frames) break;
  }
  summary.seconds = glfwGetTime() - start;
  print_summary(*loader, summary);
  return svc::Status::Ok();
}

int walk(const Options& o, CellLoader* loader) {
  if (auto reproject = choose_reprojection(o, *loader); !reproject.ok()) {
    return svc::command_line::report_failure(kProgram, reproject.status());
  }
  WalkState state;
  state.pose = Pose{o.position.value_or(default_position(*loader)), o.yaw, o.pitch};
  state.speed = o.speed * svc::walkthrough::cell_length(loader->info());
  if (!o.path.empty()) {
    auto waypoints = svc::walkthrough::read_path_file(o.path);
    if (!waypoints.ok()) return svc::command_line::report_failure(kProgram, waypoints.status());
    std::vector<glm::dvec3> points;
    for (const auto& p : *waypoints) points.emplace_back(p[0], p[1], p[2]);
    state.walk.emplace(std::move(points), state.speed);
  }
  auto window = Window::create(o.width, o.height, true, std::string(kProgram) + " " + o.input);
  if (!window.ok()) return svc::command_line::report_failure(kProgram, window.status());
  auto renderer = Renderer::create();
  if (!renderer.ok()) return svc::command_line::report_failure(kProgram, renderer.status());
  glfwGetCursorPos((*window)->handle(), &state.cursor.x, &state.cursor.y);
  const svc::Status status = walk_loop(o, loader, window->get(), renderer->get(), &state);
  if (!status.ok()) return svc::command_line::report_failure(kProgram, status);
  return svc::command_line::interrupted() ? svc::command_line::interrupted_exit_code() : 0;
}

int gl_info() {
  auto window = Window::create(64, 64, false, kProgram);
  if (!window.ok()) return svc::command_line::report_failure(kProgram, window.status());
  std::printf("%s\n", (*window)->describe_context().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Walk through an .svc database with OpenGL, or render one frame of it into a PNG."};
  Options o;
  add_options(&app, &o);
  app.footer(
      "Keys: W A S D move, Q E down and up, Shift faster, mouse with the left button held looks around, R "
      "toggles reprojection, O the overlay, Escape quits.\n\n" +
      svc::command_line::exit_codes_help(true));
  if (auto exit_code = svc::command_line::parse(app, argc, argv, kProgram)) return *exit_code;
  if (auto problem = parse_view_options(&o)) {
    std::fprintf(stderr, "%s: %s\n", kProgram, problem->c_str());
    return svc::command_line::kExitUsage;
  }
  svc::command_line::stop_on_interrupt();
  if (o.gl_info) return gl_info();
  auto loader = CellLoader::open(o.input, !o.no_reprojection);
  if (!loader.ok()) return svc::command_line::report_failure(kProgram, loader.status());
  if (o.screenshot.empty() && o.views.empty()) return walk(o, loader->get());
  std::vector<Shot> shots;
  if (!o.screenshot.empty()) {
    shots.push_back(Shot{o.position.value_or(default_position(**loader)), o.yaw, o.pitch, o.screenshot});
  } else if (auto read = read_views(o.views); read.ok()) {
    shots = std::move(read).value();
  } else {
    return svc::command_line::report_failure(kProgram, read.status());
  }
  for (const Shot& shot : shots) {
    const svc::Status writable =
        svc::command_line::check_output(shot.output, svc::command_line::OutputKind::kFile, o.overwrite, {o.input});
    if (!writable.ok()) return svc::command_line::report_failure(kProgram, writable);
  }
  return screenshots(o, loader->get(), shots);
}
