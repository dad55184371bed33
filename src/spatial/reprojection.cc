#include "spatial/reprojection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace svc {
namespace {

// Points closer to the reference camera plane than this (scene units, or direction
// units for background) count as behind it: their projection is meaningless or huge.
constexpr double kMinDepthInFront = 1e-9;

bool is_background(float z, const Frustum& frustum) {
  return !(z > 0.0f) || !std::isfinite(z) || static_cast<double>(z) >= frustum.far_plane;
}

FlowField empty_field(int width, int height) {
  FlowField flow;
  flow.width = std::max(width, 0);
  flow.height = std::max(height, 0);
  const size_t n = static_cast<size_t>(flow.width) * static_cast<size_t>(flow.height);
  flow.dx.assign(n, 0.0f);
  flow.dy.assign(n, 0.0f);
  flow.valid.assign(n, 0);
  return flow;
}

glm::dmat4 view_matrix(const Camera& camera) {
  return glm::make_mat4(camera.world_to_camera.data());
}

glm::dmat4 projection_matrix(const Frustum& f) {
  return glm::frustum(f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane);
}

// The dissertation's windowing transform W, for OpenGL window coordinates (y up).
glm::dmat4 window_matrix(int width, int height) {
  glm::dmat4 w(1.0);
  w[0][0] = width / 2.0;
  w[3][0] = width / 2.0;
  w[1][1] = height / 2.0;
  w[3][1] = height / 2.0;
  w[2][2] = 0.5;
  w[3][2] = 0.5;
  return w;
}

// Rounds d pixels to half pixels, halves away from zero, when the result lies within
// +-limit (limit <= 32767); false otherwise (also for NaN). Agrees with quantize_flow:
// for a float d, twice +- 0.5 is exact in double, so truncating it rounds correctly.
inline bool half_pels_within(float d, int limit, int16_t* out) {
  const double twice = static_cast<double>(d) * 2.0;
  if (!(std::abs(twice) < limit + 0.5)) return false;
  const int rounded = static_cast<int>(twice + (twice >= 0 ? 0.5 : -0.5));
  if (rounded > limit || rounded < -limit) return false;
  *out = static_cast<int16_t>(rounded);
  return true;
}

}  // namespace

FlowField compute_flow(const Camera& current, const Camera& reference, int width, int height,
                       const std::vector<float>& depth) {
  FlowField flow = empty_field(width, height);
  if (depth.size() != flow.dx.size() || flow.dx.empty()) return flow;

  // Current camera space -> reference camera space, once per face.
  const glm::dmat4 combined = view_matrix(reference) * glm::inverse(view_matrix(current));
  const glm::dvec3 col_x(combined[0]), col_y(combined[1]), col_z(combined[2]);
  const glm::dvec3 translation(combined[3]);

  // Ray of pixel (i, j) in current camera space at unit eye depth: (a_i, b_j, -1).
  const Frustum& cf = current.frustum;
  const double w = width, h = height;
  std::vector<glm::dvec3> column_term(static_cast<size_t>(width));
  for (int i = 0; i < width; ++i) {
    const double a = (cf.left + (i + 0.5) / w * (cf.right - cf.left)) / cf.near_plane;
    column_term[static_cast<size_t>(i)] = a * col_x;
  }

  // Reference projection: x_ndc = -(p00 * x / z) - p02, likewise y.
  const Frustum& rf = reference.frustum;
  const double p00 = 2.0 * rf.near_plane / (rf.right - rf.left);
  const double p02 = (rf.right + rf.left) / (rf.right - rf.left);
  const double p11 = 2.0 * rf.near_plane / (rf.top - rf.bottom);
  const double p12 = (rf.top + rf.bottom) / (rf.top - rf.bottom);

  for (int j = 0; j < height; ++j) {
    const double b = (cf.bottom + (1.0 - (j + 0.5) / h) * (cf.top - cf.bottom)) / cf.near_plane;
    const glm::dvec3 row_term = b * col_y - col_z;
    const size_t row = static_cast<size_t>(j) * static_cast<size_t>(width);
    for (int i = 0; i < width; ++i) {
      const size_t k = row + static_cast<size_t>(i);
      const glm::dvec3 direction = column_term[static_cast<size_t>(i)] + row_term;
      const float z = depth[k];
      // Background is a point at infinity: only the direction moves (rotation only).
      const glm::dvec3 p =
          is_background(z, cf) ? direction : static_cast<double>(z) * direction + translation;
      if (!(p.z < -kMinDepthInFront)) continue;
      const double inv = -1.0 / p.z;
      const double x_ndc = p00 * p.x * inv - p02;
      const double y_ndc = p11 * p.y * inv - p12;
      const double u = (x_ndc + 1.0) * 0.5 * w - 0.5;
      const double v = (1.0 - y_ndc) * 0.5 * h - 0.5;
      const double fx = u - i, fy = v - j;
      if (!std::isfinite(fx) || !std::isfinite(fy)) continue;
      flow.dx[k] = static_cast<float>(fx);
      flow.dy[k] = static_cast<float>(fy);
      flow.valid[k] = 1;
    }
  }
  return flow;
}

FlowField compute_flow_reference(const Camera& current, const Camera& reference, int width,
                                 int height, const std::vector<float>& depth) {
  FlowField flow = empty_field(width, height);
  if (depth.size() != flow.dx.size() || flow.dx.empty()) return flow;

  const glm::dmat4 m_cur = view_matrix(current);
  const glm::dmat4 p_cur = projection_matrix(current.frustum);
  const glm::dmat4 w_mat = window_matrix(width, height);
  const glm::dmat4 m_ref = view_matrix(reference);
  const glm::dmat4 p_ref = projection_matrix(reference.frustum);
  const glm::dmat4 v_inverse = glm::inverse(m_cur) * glm::inverse(p_cur) * glm::inverse(w_mat);
  const glm::dvec4 centre = glm::inverse(m_cur) * glm::dvec4(0.0, 0.0, 0.0, 1.0);

  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const size_t k = static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i);
      const float z = depth[k];
      const bool background = is_background(z, current.frustum);
      // Window depth of eye depth z (far plane for background).
      double z_window = 1.0;
      if (!background) {
        const glm::dvec4 clip = p_cur * glm::dvec4(0.0, 0.0, -static_cast<double>(z), 1.0);
        z_window = (clip.z / clip.w + 1.0) * 0.5;
      }
      // p_world = V^-1(C_current) p_current, V = W P M.
      const glm::dvec4 screen(i + 0.5, height - (j + 0.5), z_window, 1.0);
      glm::dvec4 world = v_inverse * screen;
      world /= world.w;
      if (background) {
        world = glm::dvec4(glm::dvec3(world) - glm::dvec3(centre / centre.w), 0.0);
      }
      // p_reference = V(C_reference) p_world.
      const glm::dvec4 clip = p_ref * m_ref * world;
      if (!(clip.w > kMinDepthInFront)) continue;
      const glm::dvec4 window = w_mat * (clip / clip.w);
      const double u = window.x - 0.5;
      const double v = height - window.y - 0.5;
      const double fx = u - i, fy = v - j;
      if (!std::isfinite(fx) || !std::isfinite(fy)) continue;
      flow.dx[k] = static_cast<float>(fx);
      flow.dy[k] = static_cast<float>(fy);
      flow.valid[k] = 1;
    }
  }
  return flow;
}

codec::MotionVector quantize_flow(double dx, double dy) {
  auto to_half_pel = [](double d) -> int16_t {
    const double half_pels = std::round(d * 2.0);  // halves away from zero
    if (!(half_pels > -32767.0)) return -32767;    // NaN saturates low
    if (half_pels > 32767.0) return 32767;
    return static_cast<int16_t>(half_pels);
  };
  return codec::MotionVector{to_half_pel(dx), to_half_pel(dy)};
}

codec::FaceCandidates macroblock_candidates(const FlowField& flow) {
  constexpr int kMb = codec::kMacroblockSize;
  const int mbs_x = (flow.width + kMb - 1) / kMb;
  const int mbs_y = (flow.height + kMb - 1) / kMb;
  codec::FaceCandidates result(static_cast<size_t>(std::max(mbs_x, 0)) *
                               static_cast<size_t>(std::max(mbs_y, 0)));
  const size_t n = static_cast<size_t>(std::max(flow.width, 0)) *
                   static_cast<size_t>(std::max(flow.height, 0));
  if (n == 0 || flow.dx.size() != n || flow.dy.size() != n || flow.valid.size() != n) {
    return result;
  }
  const int limit = std::min(2 * std::max(flow.width, flow.height), 32767);

  // A vector's key orders vectors by y, then x: key = y * 65536 + x.
  struct Counted {
    int32_t key;
    int count;
  };
  // Per macroblock: count keys in a small open-addressing table (a generation stamp per
  // slot avoids clearing it), then order the distinct keys by count. The order is total
  // (count descending, then key ascending), so the result is deterministic.
  constexpr int kSlots = 1024;  // > 4 x 256 keys: short probe sequences
  std::array<int32_t, kSlots> slot_key{};
  std::array<int32_t, kSlots> slot_index{};
  std::array<uint32_t, kSlots> slot_generation{};
  uint32_t generation = 0;
  std::array<Counted, kMb * kMb> distinct;

  for (int mby = 0; mby < mbs_y; ++mby) {
    for (int mbx = 0; mbx < mbs_x; ++mbx) {
      ++generation;
      int distinct_count = 0;
      const int y_end = std::min(flow.height, (mby + 1) * kMb);
      const int x_end = std::min(flow.width, (mbx + 1) * kMb);
      for (int y = mby * kMb; y < y_end; ++y) {
        for (int x = mbx * kMb; x < x_end; ++x) {
          const size_t k = static_cast<size_t>(y) * static_cast<size_t>(flow.width) +
                           static_cast<size_t>(x);
          if (!flow.valid[k]) continue;
          codec::MotionVector v;
          if (!half_pels_within(flow.dx[k], limit, &v.x) ||
              !half_pels_within(flow.dy[k], limit, &v.y)) {
            continue;
          }
          const int32_t key = v.y * 65536 + v.x;
          uint32_t slot = (static_cast<uint32_t>(key) * 2654435761u) >> 22;  // 10 bits
          while (slot_generation[slot] == generation && slot_key[slot] != key) slot = (slot + 1) & (kSlots - 1);
          if (slot_generation[slot] != generation) {
            slot_generation[slot] = generation;
            slot_key[slot] = key;
            slot_index[slot] = distinct_count;
            distinct[static_cast<size_t>(distinct_count++)] = {key, 0};
          }
          ++distinct[static_cast<size_t>(slot_index[slot])].count;
        }
      }
      if (distinct_count == 0) continue;
      const int kept = std::min(distinct_count, kMaxCandidatesPerMacroblock);
      std::partial_sort(distinct.begin(), distinct.begin() + kept, distinct.begin() + distinct_count,
                        [](const Counted& l, const Counted& r) {
                          return l.count != r.count ? l.count > r.count : l.key < r.key;
                        });
      codec::CandidateList& list =
          result[static_cast<size_t>(mby) * static_cast<size_t>(mbs_x) + static_cast<size_t>(mbx)];
      list.reserve(static_cast<size_t>(kept));
      for (int d = 0; d < kept; ++d) {
        const Counted& c = distinct[static_cast<size_t>(d)];
        // Unpack: x is the low 16 bits as signed, y the rest.
        const auto x = static_cast<int16_t>(static_cast<uint16_t>(c.key & 0xffff));
        const auto y = static_cast<int16_t>((c.key - x) / 65536);
        list.push_back(codec::MotionVector{x, y});
      }
    }
  }
  return result;
}

codec::WarpField warp_nodes(const FlowField& flow) {
  constexpr int kMb = codec::kMacroblockSize;
  codec::WarpField field;
  const size_t n = static_cast<size_t>(std::max(flow.width, 0)) * static_cast<size_t>(std::max(flow.height, 0));
  if (n == 0 || flow.dx.size() != n || flow.dy.size() != n || flow.valid.size() != n) return field;
  field.nodes_x = (flow.width + kMb - 1) / kMb + 1;
  field.nodes_y = (flow.height + kMb - 1) / kMb + 1;
  field.nodes.assign(static_cast<size_t>(field.nodes_x) * field.nodes_y, codec::WarpNode{});
  std::vector<uint8_t> has(field.nodes.size(), 0);
  // Components beyond this many pixels are not representable by any decoder.
  const double limit = 2.0 * std::max(flow.width, flow.height) + 32.0;
  auto to_node = [](double pixels) {
    return static_cast<int32_t>(std::lround(pixels * codec::kWarpNodeUnitsPerPixel));
  };
  for (int j = 0; j < field.nodes_y; ++j) {
    for (int i = 0; i < field.nodes_x; ++i) {
      // The 4x4 pixels around the corner, clamped to the face; the inner 2x2 first.
      float xs[16], ys[16];
      int count = 0, inner = 0;
      for (int pass = 0; pass < 2; ++pass) {
        for (int dy = -2; dy < 2; ++dy) {
          for (int dx = -2; dx < 2; ++dx) {
            const bool is_inner = dx >= -1 && dx <= 0 && dy >= -1 && dy <= 0;
            if (is_inner != (pass == 0)) continue;
            const int x = std::clamp(kMb * i + dx, 0, flow.width - 1), y = std::clamp(kMb * j + dy, 0, flow.height - 1);
            const size_t k = static_cast<size_t>(y) * static_cast<size_t>(flow.width) + static_cast<size_t>(x);
            if (!flow.valid[k] || !(std::abs(flow.dx[k]) < limit) || !(std::abs(flow.dy[k]) < limit)) continue;
            xs[count] = flow.dx[k];
            ys[count] = flow.dy[k];
            ++count;
          }
        }
        if (pass == 0) inner = count;
      }
      if (count == 0) continue;
      double mean_x = 0, mean_y = 0, lo_x = 1e30, hi_x = -1e30, lo_y = 1e30, hi_y = -1e30;
      for (int p = 0; p < inner; ++p) {
        mean_x += xs[p];
        mean_y += ys[p];
        lo_x = std::min<double>(lo_x, xs[p]);
        hi_x = std::max<double>(hi_x, xs[p]);
        lo_y = std::min<double>(lo_y, ys[p]);
        hi_y = std::max<double>(hi_y, ys[p]);
      }
      codec::WarpNode& node = field.nodes[static_cast<size_t>(j) * field.nodes_x + i];
      if (inner > 0 && hi_x - lo_x <= 0.5 && hi_y - lo_y <= 0.5) {
        node = codec::WarpNode{to_node(mean_x / inner), to_node(mean_y / inner)};
      } else {
        int best = 0;
        double best_distance = 1e300;
        for (int p = 0; p < count; ++p) {
          double distance = 0;
          for (int q = 0; q < count; ++q) distance += std::abs(xs[p] - xs[q]) + std::abs(ys[p] - ys[q]);
          if (distance < best_distance) {
            best_distance = distance;
            best = p;
          }
        }
        node = codec::WarpNode{to_node(xs[best]), to_node(ys[best])};
      }
      has[static_cast<size_t>(j) * field.nodes_x + i] = 1;
    }
  }
  // Fill nodes without flow from valid neighbours, a ring at a time.
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<uint8_t> next = has;
    for (int j = 0; j < field.nodes_y; ++j) {
      for (int i = 0; i < field.nodes_x; ++i) {
        const size_t k = static_cast<size_t>(j) * field.nodes_x + i;
        if (has[k]) continue;
        int64_t sx = 0, sy = 0;
        int m = 0;
        const int offsets[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
        for (const auto& o : offsets) {
          const int x = i + o[0], y = j + o[1];
          if (x < 0 || y < 0 || x >= field.nodes_x || y >= field.nodes_y) continue;
          const size_t q = static_cast<size_t>(y) * field.nodes_x + x;
          if (!has[q]) continue;
          sx += field.nodes[q].x;
          sy += field.nodes[q].y;
          ++m;
        }
        if (m == 0) continue;
        field.nodes[k] = codec::WarpNode{static_cast<int32_t>(sx / m), static_cast<int32_t>(sy / m)};
        next[k] = 1;
        changed = true;
      }
    }
    has.swap(next);
  }
  return field;
}

CandidateStats candidate_stats(const codec::FaceCandidates& candidates) {
  CandidateStats stats;
  stats.macroblocks = candidates.size();
  for (const auto& list : candidates) {
    if (!list.empty()) ++stats.macroblocks_with_candidates;
    stats.candidates += list.size();
  }
  return stats;
}

double mean_candidates_per_macroblock(const codec::FaceCandidates& candidates) {
  return candidate_stats(candidates).mean_per_macroblock();
}

}  // namespace svc
