// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/reprojection.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "spatial/camera_terms.h"
#include "spatial/flow_kernels.h"

namespace svc {
namespace {

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

glm::dmat4 view_matrix(const Camera& camera) { return glm::make_mat4(camera.world_to_camera.data()); }

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

}  // namespace

void compute_flow(const Camera& current, const Camera& reference, int width, int height,
                  const std::vector<float>& depth, FlowField* out) {
  FlowField& flow = *out;
  flow.width = std::max(width, 0);
  flow.height = std::max(height, 0);
  const size_t n = static_cast<size_t>(flow.width) * static_cast<size_t>(flow.height);
  if (depth.size() != n || n == 0) {
    flow = empty_field(width, height);
    return;
  }
  // Every pixel is written below: storage kept from an earlier call needs no clearing.
  flow.dx.resize(n);
  flow.dy.resize(n);
  flow.valid.resize(n);

  // Current camera space -> reference camera space, once per face.
  const glm::dmat4 combined = current_to_reference(current, reference);
  const glm::dvec3 col_x(combined[0]), col_y(combined[1]), col_z(combined[2]);
  const glm::dvec3 translation(combined[3]);

  // Ray of pixel (i, j) in current camera space at unit eye depth: (a_i, b_j, -1).
  const Frustum& cf = current.frustum;
  const double w = width, h = height;
  // Column terms as separate arrays so that two pixels load at once.
  std::vector<double> column_x(static_cast<size_t>(width)), column_y(column_x.size()), column_z(column_x.size());
  for (int i = 0; i < width; ++i) {
    const double a = (cf.left + (i + 0.5) / w * (cf.right - cf.left)) / cf.near_plane;
    const glm::dvec3 term = a * col_x;
    column_x[static_cast<size_t>(i)] = term.x;
    column_y[static_cast<size_t>(i)] = term.y;
    column_z[static_cast<size_t>(i)] = term.z;
  }

  const ProjectionTerms projection = projection_terms(reference.frustum);
  const FlowKernels& kernels = get_flow_kernels();
  FlowRow flow_row{column_x.data(),
                   column_y.data(),
                   column_z.data(),
                   0,
                   0,
                   0,
                   translation.x,
                   translation.y,
                   translation.z,
                   projection.p00,
                   projection.p02,
                   projection.p11,
                   projection.p12,
                   w,
                   h,
                   cf.far_plane,
                   0,
                   width};
  for (int j = 0; j < height; ++j) {
    const double b = (cf.bottom + (1.0 - (j + 0.5) / h) * (cf.top - cf.bottom)) / cf.near_plane;
    const glm::dvec3 row_term = b * col_y - col_z;
    flow_row.row_x = row_term.x;
    flow_row.row_y = row_term.y;
    flow_row.row_z = row_term.z;
    flow_row.row = j;
    const size_t row = static_cast<size_t>(j) * static_cast<size_t>(width);
    kernels.flow_row(flow_row, &depth[row], &flow.dx[row], &flow.dy[row], &flow.valid[row]);
  }
}

FlowField compute_flow(const Camera& current, const Camera& reference, int width, int height,
                       const std::vector<float>& depth) {
  FlowField flow;
  compute_flow(current, reference, width, height, depth, &flow);
  return flow;
}

FlowField compute_flow_reference(const Camera& current, const Camera& reference, int width, int height,
                                 const std::vector<float>& depth) {
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

std::vector<uint8_t> visible_in_reference(const Camera& current, const Camera& reference, int width, int height,
                                          const std::vector<float>& depth,
                                          const std::vector<float>& reference_depth) {
  const size_t n = static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0));
  std::vector<uint8_t> seen(n, 0);
  if (n == 0 || depth.size() != n || reference_depth.size() != n) return seen;
  const FlowField flow = compute_flow(current, reference, width, height, depth);
  // Eye z in the reference camera of the point each pixel shows.
  const glm::dmat4 combined = current_to_reference(current, reference);
  const Frustum& cf = current.frustum;
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const size_t k = static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i);
      if (!flow.valid[k]) continue;
      const double x = i + static_cast<double>(flow.dx[k]), y = j + static_cast<double>(flow.dy[k]);
      if (!(x >= -0.5 && y >= -0.5 && x < width - 0.5 && y < height - 0.5)) continue;
      const int landing_x = static_cast<int>(std::lround(x)), landing_y = static_cast<int>(std::lround(y));
      const bool background = is_background(depth[k], cf);
      double reference_z = 0;
      if (!background) {
        const double a = (cf.left + (i + 0.5) / width * (cf.right - cf.left)) / cf.near_plane;
        const double b = (cf.bottom + (1.0 - (j + 0.5) / height) * (cf.top - cf.bottom)) / cf.near_plane;
        const double z = depth[k];
        reference_z = -(combined * glm::dvec4(a * z, b * z, -z, 1.0)).z;
      }
      bool found = false;
      for (int dy = -1; dy <= 1 && !found; ++dy) {
        for (int dx = -1; dx <= 1 && !found; ++dx) {
          const int rx = std::clamp(landing_x + dx, 0, width - 1), ry = std::clamp(landing_y + dy, 0, height - 1);
          const float r =
              reference_depth[static_cast<size_t>(ry) * static_cast<size_t>(width) + static_cast<size_t>(rx)];
          if (background) {
            found = is_background(r, reference.frustum);
          } else if (!is_background(r, reference.frustum)) {
            found = std::abs(static_cast<double>(r) - reference_z) <= kVisibilityTolerance * reference_z;
          }
        }
      }
      seen[k] = found ? 1 : 0;
    }
  }
  return seen;
}

// One function (about 150 lines) on purpose: its scratch tables (histogram, hash slots,
// run buffers) are set up once and reused, uncleared, by every macroblock of the face.
codec::FaceCandidates macroblock_candidates(const FlowField& flow) {
  constexpr int kMb = codec::kMacroblockSize;
  const int mbs_x = (flow.width + kMb - 1) / kMb;
  const int mbs_y = (flow.height + kMb - 1) / kMb;
  codec::FaceCandidates result(static_cast<size_t>(std::max(mbs_x, 0)) * static_cast<size_t>(std::max(mbs_y, 0)));
  const size_t n = static_cast<size_t>(std::max(flow.width, 0)) * static_cast<size_t>(std::max(flow.height, 0));
  if (n == 0 || flow.dx.size() != n || flow.dy.size() != n || flow.valid.size() != n) {
    return result;
  }
  const int limit = std::min(codec::kVectorUnitsPerPixel * std::max(flow.width, flow.height), 32767);

  // A vector's key orders vectors by y, then x: key = y * 65536 + x. No valid key equals
  // kNoKey (|x|, |y| <= 32767).
  constexpr int32_t kNoKey = std::numeric_limits<int32_t>::min();
  struct Counted {
    int32_t key;
    int count;
  };
  // Per macroblock: runs of equal keys along its rows, then their counts. When the vectors
  // span a small box (the usual case: flow is smooth) runs are counted in a histogram over
  // that box (only the bins touched are read back); otherwise in a small open-addressing
  // table whose generation stamp avoids clearing it. The distinct keys are then ordered by
  // count; the order is total (count descending, then key ascending), so the order they
  // were found in does not matter and both ways give the same lists.
  constexpr int kSlots = 1024;  // > 4 x 256 keys: short probe sequences
  struct Slot {
    uint32_t generation;
    int32_t key;
    int32_t index;
  };
  std::array<Slot, kSlots> slots{};
  uint32_t generation = 0;
  constexpr int kHistogramBins = 1024;
  std::array<uint16_t, kHistogramBins> bins{};  // all zero between macroblocks
  std::array<Counted, kMb * kMb> distinct;
  std::array<Counted, kMb * kMb> runs;
  std::array<uint64_t, kMb * kMb> ordered;
  std::array<int, kMb * kMb> touched;
  auto key_x = [](int32_t key) { return static_cast<int16_t>(static_cast<uint16_t>(key & 0xffff)); };
  auto key_y = [&](int32_t key) { return static_cast<int16_t>((key - key_x(key)) >> 16); };  // exact: a multiple

  // Keys of one stripe of macroblocks (16 rows) in a linear pass, then macroblock by
  // macroblock: a stripe's keys stay in cache where a whole face's would not.
  const size_t width = static_cast<size_t>(flow.width);
  const FlowKernels& flow_kernels = get_flow_kernels();
  std::vector<int32_t> stripe_keys(static_cast<size_t>(kMb) * width);

  for (int mby = 0; mby < mbs_y; ++mby) {
    const size_t stripe_begin = static_cast<size_t>(mby) * kMb * width;
    const size_t stripe_pixels = static_cast<size_t>(std::min(kMb, flow.height - mby * kMb)) * width;
    flow_kernels.quarter_pel_keys(flow.dx.data() + stripe_begin, flow.dy.data() + stripe_begin,
                                  flow.valid.data() + stripe_begin, stripe_pixels, limit, kNoKey,
                                  stripe_keys.data());
    for (int mbx = 0; mbx < mbs_x; ++mbx) {
      int distinct_count = 0;
      const int y_begin = mby * kMb, y_end = std::min(flow.height, (mby + 1) * kMb);
      const int x_begin = mbx * kMb, x_end = std::min(flow.width, (mbx + 1) * kMb);
      const int row_length = x_end - x_begin;
      // Runs of equal keys along the macroblock's rows (flow is smooth, so runs are long):
      // the box and both counters work on runs, not pixels, which also keeps consecutive
      // increments off the same histogram bin.
      int run_count = 0;
      int min_x = 32767, max_x = -32767, min_y = 32767, max_y = -32767;
      auto add_run = [&](int32_t key, int length) {
        if (key == kNoKey) return;
        runs[static_cast<size_t>(run_count++)] = {key, length};
        min_x = std::min<int>(min_x, key_x(key));
        max_x = std::max<int>(max_x, key_x(key));
        min_y = std::min<int>(min_y, key_y(key));
        max_y = std::max<int>(max_y, key_y(key));
      };
      for (int y = y_begin; y < y_end; ++y) {
        const int32_t* row = stripe_keys.data() + static_cast<size_t>(y - y_begin) * width + x_begin;
        if (row_length == kMb) {
          // Whole rows: one mask of where runs end, so the loop turns once per run
          // without a hard-to-predict branch per pixel.
          unsigned ends = flow_kernels.run_ends_16(row);
          int start = 0;
          while (ends != 0) {
            const int end = std::countr_zero(ends);
            ends &= ends - 1;
            add_run(row[start], end + 1 - start);
            start = end + 1;
          }
          continue;
        }
        for (int i = 0; i < row_length;) {
          const int32_t key = row[i];
          int end = i + 1;
          while (end < row_length && row[end] == key) ++end;
          add_run(key, end - i);
          i = end;
        }
      }
      if (run_count == 0) continue;  // no usable pixel
      const int box_width = max_x - min_x + 1, box_height = max_y - min_y + 1;
      if (box_height <= kHistogramBins / box_width) {
        // Only the bins a run touched are read back: a wide box is mostly empty.
        int touched_count = 0;
        for (int r = 0; r < run_count; ++r) {
          const Counted& run = runs[static_cast<size_t>(r)];
          const int bin = (key_y(run.key) - min_y) * box_width + (key_x(run.key) - min_x);
          if (bins[static_cast<size_t>(bin)] == 0) touched[static_cast<size_t>(touched_count++)] = bin;
          bins[static_cast<size_t>(bin)] = static_cast<uint16_t>(bins[static_cast<size_t>(bin)] + run.count);
        }
        for (int t = 0; t < touched_count; ++t) {
          const int bin = touched[static_cast<size_t>(t)];
          const int by = bin / box_width, bx = bin - by * box_width;
          distinct[static_cast<size_t>(distinct_count++)] = {(min_y + by) * 65536 + (min_x + bx),
                                                             bins[static_cast<size_t>(bin)]};
          bins[static_cast<size_t>(bin)] = 0;
        }
      } else {
        ++generation;
        for (int r = 0; r < run_count; ++r) {
          const Counted& run = runs[static_cast<size_t>(r)];
          uint32_t slot = (static_cast<uint32_t>(run.key) * 2654435761u) >> 22;  // 10 bits
          while (slots[slot].generation == generation && slots[slot].key != run.key)
            slot = (slot + 1) & (kSlots - 1);
          if (slots[slot].generation != generation) {
            slots[slot] = {generation, run.key, distinct_count};
            distinct[static_cast<size_t>(distinct_count++)] = {run.key, 0};
          }
          distinct[static_cast<size_t>(slots[slot].index)].count += run.count;
        }
      }
      if (distinct_count == 0) continue;
      const int kept = std::min(distinct_count, kMaxCandidatesPerMacroblock);
      // Count descending, then key ascending, as one unsigned integer order: the count's
      // complement above the key with its sign bit flipped.
      for (int d = 0; d < distinct_count; ++d) {
        const Counted& c = distinct[static_cast<size_t>(d)];
        ordered[static_cast<size_t>(d)] = static_cast<uint64_t>(0xffff - c.count) << 32 |
                                          (static_cast<uint32_t>(c.key) ^ 0x80000000u);
      }
      if (kept == distinct_count) {
        std::sort(ordered.begin(), ordered.begin() + distinct_count);
      } else {
        std::partial_sort(ordered.begin(), ordered.begin() + kept, ordered.begin() + distinct_count);
      }
      codec::CandidateList& list =
          result[static_cast<size_t>(mby) * static_cast<size_t>(mbs_x) + static_cast<size_t>(mbx)];
      list.resize(static_cast<size_t>(kept));
      for (int d = 0; d < kept; ++d) {
        const auto key = static_cast<int32_t>(static_cast<uint32_t>(ordered[static_cast<size_t>(d)]) ^ 0x80000000u);
        list[static_cast<size_t>(d)] = codec::MotionVector{key_x(key), key_y(key)};
      }
    }
  }
  return result;
}

codec::FaceCandidates block_candidates(const FlowField& flow) {
  constexpr int kBlock = codec::kMacroblockSize / 2;
  const int blocks_x = 2 * ((flow.width + codec::kMacroblockSize - 1) / codec::kMacroblockSize);
  const int blocks_y = 2 * ((flow.height + codec::kMacroblockSize - 1) / codec::kMacroblockSize);
  codec::FaceCandidates result(static_cast<size_t>(std::max(blocks_x, 0)) *
                               static_cast<size_t>(std::max(blocks_y, 0)));
  const size_t n = static_cast<size_t>(std::max(flow.width, 0)) * static_cast<size_t>(std::max(flow.height, 0));
  if (n == 0 || flow.dx.size() != n || flow.dy.size() != n || flow.valid.size() != n) return result;
  const int limit = std::min(codec::kVectorUnitsPerPixel * std::max(flow.width, flow.height), 32767);
  constexpr int32_t kNoKey = std::numeric_limits<int32_t>::min();
  const FlowKernels& flow_kernels = get_flow_kernels();
  std::array<int32_t, kBlock * kBlock> keys;
  std::array<int32_t, kBlock> row_keys;
  std::array<std::pair<int, int32_t>, kBlock * kBlock> counted;  // (-count, key): the order wanted
  for (int by = 0; by < blocks_y; ++by) {
    for (int bx = 0; bx < blocks_x; ++bx) {
      const int x_begin = bx * kBlock, x_end = std::min(flow.width, x_begin + kBlock);
      const int y_begin = by * kBlock, y_end = std::min(flow.height, y_begin + kBlock);
      size_t key_count = 0;
      for (int y = y_begin; y < y_end && x_begin < x_end; ++y) {
        const size_t at = static_cast<size_t>(y) * static_cast<size_t>(flow.width) + static_cast<size_t>(x_begin);
        const size_t length = static_cast<size_t>(x_end - x_begin);
        flow_kernels.quarter_pel_keys(flow.dx.data() + at, flow.dy.data() + at, flow.valid.data() + at, length,
                                      limit, kNoKey, row_keys.data());
        for (size_t i = 0; i < length; ++i) {
          if (row_keys[i] != kNoKey) keys[key_count++] = row_keys[i];
        }
      }
      std::sort(keys.begin(), keys.begin() + static_cast<ptrdiff_t>(key_count));
      size_t distinct = 0;
      for (size_t i = 0; i < key_count;) {
        size_t end = i + 1;
        while (end < key_count && keys[end] == keys[i]) ++end;
        counted[distinct++] = {-static_cast<int>(end - i), keys[i]};
        i = end;
      }
      std::sort(counted.begin(), counted.begin() + static_cast<ptrdiff_t>(distinct));
      codec::CandidateList& list = result[static_cast<size_t>(by) * static_cast<size_t>(blocks_x) + bx];
      const size_t kept = std::min(distinct, static_cast<size_t>(kMaxCandidatesPerMacroblock));
      for (size_t d = 0; d < kept; ++d) {
        const int32_t key = counted[d].second;
        const auto x = static_cast<int16_t>(static_cast<uint16_t>(key & 0xffff));
        list.push_back(codec::MotionVector{x, static_cast<int16_t>((key - x) >> 16)});
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
            const int x = std::clamp(kMb * i + dx, 0, flow.width - 1),
                      y = std::clamp(kMb * j + dy, 0, flow.height - 1);
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

}  // namespace svc
