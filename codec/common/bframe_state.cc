// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/bframe_state.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <string>

#include "codec/common/context_priors.h"
#include "codec/common/cube_padding.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/image_planes.h"

namespace svc::codec {

int reference_border_units(int extra) {
  const int unit = 2 * kCubeBorderUnitPixels;
  if (extra < 0 || extra % unit != 0 || extra / unit > kMaxCubeBorderUnits) return -1;
  return extra / unit;
}

}  // namespace svc::codec

namespace svc::codec::bframe {

void init_state(FrameState& s, int width, int height, int qindex, const ImageYCbCr420* ref0,
                const ImageYCbCr420* ref1, int border_mbs) {
  // Every field as in a fresh state; the buffers keep their capacity, so that a state
  // reused frame after frame allocates nothing.
  FrameState fresh;
  fresh.nodes.swap(s.nodes);
  fresh.node_known.swap(s.node_known);
  fresh.planes.swap(s.planes);
  fresh.coded.swap(s.coded);
  fresh.intra_planes.swap(s.intra_planes);
  fresh.macroblocks.swap(s.macroblocks);
  s = std::move(fresh);
  s.width = width;
  s.border_mbs = border_mbs;
  s.height = height;
  s.mbs_x = (width + 15) / 16;
  s.mbs_y = (height + 15) / 16;
  s.chroma_width = (width + 1) / 2;
  s.chroma_height = (height + 1) / 2;
  s.references = {ref0, ref1};
  s.reference_count = ref1 != nullptr ? 2 : 1;
  s.inter_quantizer = make_residual_quantizer(TransformSize::k8x8, qindex);
  s.inter_quantizer_16x16 = make_residual_quantizer(TransformSize::k16x16, qindex);
  s.inter_quantizer_4x4 = make_residual_quantizer(TransformSize::k4x4, qindex);
  s.intra_quantizers = intra::residual_quantizers(qindex);
  s.vector_limit = max_vector_component(width, height);
  s.node_limit = max_warp_node_component(width, height);
  prime_bframe_contexts(s.contexts);
  s.nodes_x = s.mbs_x + 1;
  s.nodes_y = s.mbs_y + 1;
  for (int r = 0; r < 2; ++r) {
    s.nodes[r].assign(static_cast<size_t>(s.nodes_x) * s.nodes_y, WarpNode{});
    s.node_known[r].assign(s.nodes[r].size(), 0);
  }
  s.strides = {16 * s.mbs_x, 8 * s.mbs_x, 8 * s.mbs_x};
  const size_t luma_size = static_cast<size_t>(16 * s.mbs_x) * (16 * s.mbs_y);
  s.planes[0].assign(luma_size, 0);
  s.planes[1].assign(luma_size / 4, 0);
  s.planes[2].assign(luma_size / 4, 0);
  const size_t mb_count = static_cast<size_t>(s.mbs_x) * s.mbs_y;
  s.coded[0].assign(4 * mb_count, 0);
  for (int p = 1; p < 3; ++p) s.coded[p].assign(mb_count, 0);
  s.intra_planes.clear();
  for (int p = 0; p < 3; ++p) s.intra_planes.emplace_back(s.strides[p], p == 0 ? 16 * s.mbs_y : 8 * s.mbs_y);
  s.macroblocks.assign(mb_count, MacroblockInfo{});
}

int coded_context(const FrameState& s, const uint8_t* local, int plane, int mx, int my, int bx, int by) {
  return (bx > 0 ? block_value(s, s.coded[plane], local, plane, mx, my, bx - 1, by) : 0) +
         (by > 0 ? block_value(s, s.coded[plane], local, plane, mx, my, bx, by - 1) : 0);
}

namespace {

// The median predictor of 4.2 over the neighbours' vectors as `at(nx, ny)` gives them.
template <class VectorAt>
MotionVector median_predictor(const FrameState& s, int mx, int my, VectorAt at) {
  if (my == 0) return mx == 0 ? MotionVector{} : at(mx - 1, 0);
  const MotionVector top = at(mx, my - 1);
  const MotionVector left = mx > 0 ? at(mx - 1, my) : top;
  const MotionVector diagonal = mx + 1 < s.mbs_x ? at(mx + 1, my - 1) : mx > 0 ? at(mx - 1, my - 1) : top;
  return MotionVector{static_cast<int16_t>(median3(left.x, top.x, diagonal.x)),
                      static_cast<int16_t>(median3(left.y, top.y, diagonal.y))};
}

}  // namespace

MotionVector predict_vector(const FrameState& s, int mx, int my, int reference) {
  return median_predictor(s, mx, my, [&](int nx, int ny) { return s.mb(nx, ny).vectors[reference]; });
}

CarriedVector carried_vector(const FrameState& s, int r, int nx, int ny, LineDirection here) {
  const MotionVector v = s.mb(nx, ny).vectors[r];
  int64_t x = 0, y = 0;
  if (!carry_along_lines(v.x, v.y, macroblock_direction(s, r, nx, ny), here, &x, &y)) return {v, false};
  if (std::llabs(x) > s.vector_limit || std::llabs(y) > s.vector_limit) return {v, false};
  return {MotionVector{static_cast<int16_t>(x), static_cast<int16_t>(y)}, true};
}

void VectorPredictors::add(MotionVector v) {
  if (count == kMaxVectorPredictors ||
      std::find(vectors.begin(), vectors.begin() + count, v) != vectors.begin() + count)
    return;
  vectors[static_cast<size_t>(count++)] = v;
}

MotionVector onto_line(LineDirection d, MotionVector v, int limit) {
  if (d.x == 0 && d.y == 0) return v;
  int64_t x = 0, y = 0;
  from_line_coordinates({to_line_coordinates(v.x, v.y, d).along, 0}, d, &x, &y);
  if (std::llabs(x) > limit || std::llabs(y) > limit) return v;
  return MotionVector{static_cast<int16_t>(x), static_cast<int16_t>(y)};
}

VectorPredictors macroblock_predictors(const FrameState& s, int mx, int my, int reference) {
  VectorPredictors list;
  if (!s.lines[reference].present()) {
    list.add(predict_vector(s, mx, my, reference));
    if (mx > 0) list.add(s.mb(mx - 1, my).vectors[reference]);
    if (my > 0) list.add(s.mb(mx, my - 1).vectors[reference]);
    if (my > 0 && mx + 1 < s.mbs_x) list.add(s.mb(mx + 1, my - 1).vectors[reference]);
    return list;
  }
  const LineDirection d = macroblock_direction(s, reference, mx, my);
  // Each neighbour (left, top, top-right, top-left) carried once. A carried vector is on
  // the line, and so is the median of vectors on it (both components are monotonic in
  // the along coordinate): taking those onto the line again would change nothing.
  std::array<CarriedVector, 4> carried;
  std::array<bool, 4> done{};
  auto neighbour = [&](int nx, int ny) -> const CarriedVector& {
    const size_t slot = ny == my ? 0 : nx == mx ? 1 : nx > mx ? 2 : 3;
    if (!done[slot]) carried[slot] = carried_vector(s, reference, nx, ny, d);
    done[slot] = true;
    return carried[slot];
  };
  bool median_on_line = true;
  const MotionVector median = median_predictor(s, mx, my, [&](int nx, int ny) {
    const CarriedVector& c = neighbour(nx, ny);
    median_on_line = median_on_line && c.on_line;
    return c.vector;
  });
  auto add = [&](const CarriedVector& c) {
    list.add(c.on_line ? c.vector : onto_line(d, c.vector, s.vector_limit));
  };
  add({median, median_on_line});
  if (mx > 0) add(neighbour(mx - 1, my));
  if (my > 0) add(neighbour(mx, my - 1));
  if (my > 0 && mx + 1 < s.mbs_x) add(neighbour(mx + 1, my - 1));
  return list;
}

MacroblockMode predicted_mode(const FrameState& s, int mx, int my) {
  if (mx > 0) return s.mb(mx - 1, my).inter_mode;
  if (my > 0) return s.mb(mx, my - 1).inter_mode;
  return s.reference_count == 2 ? MacroblockMode::kBidirectional : MacroblockMode::kForward;
}

bool predicted_warp(const FrameState& s, int mx, int my) {
  if (mx > 0) return s.mb(mx - 1, my).inter_warp;
  if (my > 0) return s.mb(mx, my - 1).inter_warp;
  return false;
}

int skip_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.mode == MacroblockMode::kSkipped; });
}

int intra_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.mode == MacroblockMode::kIntra; });
}

int bidirectional_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my,
                           [](const MacroblockInfo& m) { return m.inter_mode == MacroblockMode::kBidirectional; });
}

int backward_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my,
                           [](const MacroblockInfo& m) { return m.inter_mode == MacroblockMode::kBackward; });
}

int warp_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) {
    return m.mode != MacroblockMode::kIntra && m.inter_warp;
  });
}

int luma_16x16_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.luma_16x16; });
}

int partition_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.partition != Partition::k16x16; });
}

MotionVector partition_predictor(const PartitionMotion& motion, int k, int r, MotionVector macroblock_predictor) {
  for (const int neighbour : {partition_left(motion.partition, k), partition_above(motion.partition, k)}) {
    if (neighbour >= 0 && uses_reference(motion.modes[neighbour], r)) return motion.vectors[neighbour][r];
  }
  return macroblock_predictor;
}

int skip_predictor_count(const std::array<VectorPredictors, 2>& lists, MacroblockMode mode) {
  int count = 1;
  for (int r = 0; r < 2; ++r) {
    if (uses_reference(mode, r)) count = std::max(count, lists[static_cast<size_t>(r)].count);
  }
  return count;
}

std::array<MotionVector, 2> skip_vectors(const std::array<VectorPredictors, 2>& lists, MacroblockMode mode,
                                         int index) {
  std::array<MotionVector, 2> vectors = {lists[0].vectors[0], lists[1].vectors[0]};
  for (int r = 0; r < 2; ++r) {
    const VectorPredictors& list = lists[static_cast<size_t>(r)];
    if (uses_reference(mode, r) && list.count > 0)
      vectors[static_cast<size_t>(r)] = list.vectors[static_cast<size_t>(std::min(index, list.count - 1))];
  }
  return vectors;
}

VectorPredictors partition_predictors(const PartitionMotion& motion, int k, int r,
                                      const VectorPredictors& macroblock) {
  VectorPredictors list;
  list.add(partition_predictor(motion, k, r, macroblock.vectors[0]));
  for (int i = 0; i < macroblock.count; ++i) list.add(macroblock.vectors[static_cast<size_t>(i)]);
  return list;
}

WarpCorners macroblock_corners(const FrameState& s, int reference, int mx, int my) {
  WarpCorners corners;
  for (int k = 0; k < 4; ++k) corners[k] = s.nodes[reference][s.node_index(corner_i(mx, k), corner_j(my, k))];
  return corners;
}

WarpNode predict_node(const FrameState& s, int r, int i, int j, MotionVector vector_predictor, int* kind) {
  auto node = [&](int x, int y) { return s.nodes[r][s.node_index(x, y)]; };
  auto planar = [](WarpNode a, WarpNode b, WarpNode c) { return WarpNode{a.x + b.x - c.x, a.y + b.y - c.y}; };
  *kind = 0;
  if (s.known(r, i - 1, j) && s.known(r, i, j - 1) && s.known(r, i - 1, j - 1)) {
    return planar(node(i - 1, j), node(i, j - 1), node(i - 1, j - 1));
  }
  if (s.known(r, i + 1, j) && s.known(r, i, j - 1) && s.known(r, i + 1, j - 1)) {
    return planar(node(i + 1, j), node(i, j - 1), node(i + 1, j - 1));
  }
  *kind = 1;
  // A neighbour's node as this node would see the same depth (itself without lines).
  auto carried = [&](int x, int y) {
    const WarpNode n = node(x, y);
    int64_t cx = 0, cy = 0;
    if (!carry_along_lines(n.x, n.y, node_direction(s, r, x, y), node_direction(s, r, i, j), &cx, &cy) ||
        std::llabs(cx) > s.node_limit || std::llabs(cy) > s.node_limit) {
      return n;
    }
    return WarpNode{static_cast<int32_t>(cx), static_cast<int32_t>(cy)};
  };
  if (s.known(r, i - 1, j)) return carried(i - 1, j);
  if (s.known(r, i, j - 1)) return carried(i, j - 1);
  if (s.known(r, i + 1, j)) return carried(i + 1, j);
  return WarpNode{2 * vector_predictor.x, 2 * vector_predictor.y};
}

MotionVector warp_centre_vector(const FrameState& s, const WarpCorners& c) {
  auto component = [&](int sum) {
    return static_cast<int16_t>(std::clamp((sum + 4) >> 3, -s.vector_limit, s.vector_limit));
  };
  return MotionVector{component(c[0].x + c[1].x + c[2].x + c[3].x), component(c[0].y + c[1].y + c[2].y + c[3].y)};
}

int mvd_context(const FrameState& s, int mx, int my, int component) {
  const int sum = (mx > 0 ? s.mb(mx - 1, my).mvd_magnitude[component] : 0) +
                  (my > 0 ? s.mb(mx, my - 1).mvd_magnitude[component] : 0);
  return sum == 0 ? 0 : (sum < 8 ? 1 : 2);
}

LineDirection macroblock_direction(const FrameState& s, int r, int mx, int my) {
  return line_direction(s.lines[r], s.width, s.height, 32 * int64_t{mx} + 16, 32 * int64_t{my} + 16);
}

LineDirection node_direction(const FrameState& s, int r, int i, int j) {
  return line_direction(s.lines[r], s.width, s.height, 32 * int64_t{i}, 32 * int64_t{j});
}

std::array<int64_t, 2> line_difference(LineDirection d, LineCoordinates v, LineCoordinates p) {
  if (d.x == 0 && d.y == 0) return {v.along - p.along, v.across - p.across};
  return {v.along - p.along, v.across};
}

void add_line_difference(LineDirection d, int64_t px, int64_t py, std::array<int64_t, 2> difference, int64_t* x,
                         int64_t* y) {
  const LineCoordinates p = to_line_coordinates(px, py, d);
  const int64_t across = d.x == 0 && d.y == 0 ? p.across + difference[1] : difference[1];
  from_line_coordinates({p.along + difference[0], across}, d, x, y);
}

std::array<int64_t, 2> vector_difference(const FrameState& s, int r, int mx, int my, MotionVector vector,
                                         MotionVector predictor) {
  const LineDirection d = macroblock_direction(s, r, mx, my);
  return line_difference(d, to_line_coordinates(vector.x, vector.y, d),
                         to_line_coordinates(predictor.x, predictor.y, d));
}

bool add_vector_difference(const FrameState& s, int r, int mx, int my, MotionVector predictor,
                           std::array<int64_t, 2> difference, MotionVector* vector) {
  int64_t x = 0, y = 0;
  add_line_difference(macroblock_direction(s, r, mx, my), predictor.x, predictor.y, difference, &x, &y);
  if (std::llabs(x) > s.vector_limit || std::llabs(y) > s.vector_limit) return false;
  *vector = MotionVector{static_cast<int16_t>(x), static_cast<int16_t>(y)};
  return true;
}

void build_prediction(const FrameState& s, int mx, int my, MacroblockMode mode,
                      const std::array<MotionVector, 2>& vectors, MacroblockPrediction* out) {
  MacroblockIntermediate first, second;
  const int first_reference = mode == MacroblockMode::kBackward ? 1 : 0;
  predict_macroblock(*s.references[first_reference], reference_mb(s, mx), reference_mb(s, my),
                     vectors[first_reference], &first, s.filter);
  if (mode == MacroblockMode::kBidirectional)
    predict_macroblock(*s.references[1], reference_mb(s, mx), reference_mb(s, my), vectors[1], &second, s.filter);
  finish_prediction(first, mode == MacroblockMode::kBidirectional ? &second : nullptr, out);
}

void build_warp_prediction(const FrameState& s, int mx, int my, MacroblockMode mode, MacroblockPrediction* out) {
  MacroblockIntermediate first, second;
  const int first_reference = mode == MacroblockMode::kBackward ? 1 : 0;
  predict_warp_macroblock(*s.references[first_reference], reference_mb(s, mx), reference_mb(s, my),
                          macroblock_corners(s, first_reference, mx, my), &first, s.filter);
  if (mode == MacroblockMode::kBidirectional) {
    predict_warp_macroblock(*s.references[1], reference_mb(s, mx), reference_mb(s, my),
                            macroblock_corners(s, 1, mx, my), &second, s.filter);
  }
  finish_prediction(first, mode == MacroblockMode::kBidirectional ? &second : nullptr, out);
}

void predict_partition(const FrameState& s, int mx, int my, const PartitionRect& rect, int reference,
                       MotionVector vector, MacroblockIntermediate* out) {
  const ImageYCbCr420& ref = *s.references[reference];
  const int x = 16 * reference_mb(s, mx) + rect.x, y = 16 * reference_mb(s, my) + rect.y;
  predict_block(ref.y.data(), ref.width, ref.height, PlaneKind::kLuma, x, y, rect.width, rect.height, vector.x,
                vector.y, out->y.data() + rect.y * 16 + rect.x, 16, s.filter);
  const int cw = (ref.width + 1) / 2, ch = (ref.height + 1) / 2;
  const size_t chroma_offset = static_cast<size_t>(rect.y / 2) * 8 + rect.x / 2;
  predict_block(ref.cb.data(), cw, ch, PlaneKind::kChroma, x / 2, y / 2, rect.width / 2, rect.height / 2, vector.x,
                vector.y, out->cb.data() + chroma_offset, 8, s.filter);
  predict_block(ref.cr.data(), cw, ch, PlaneKind::kChroma, x / 2, y / 2, rect.width / 2, rect.height / 2, vector.x,
                vector.y, out->cr.data() + chroma_offset, 8, s.filter);
}

void build_partition_prediction(const FrameState& s, int mx, int my, const PartitionMotion& motion,
                                MacroblockPrediction* out) {
  MacroblockIntermediate first, second;
  for (int k = 0; k < partition_count(motion.partition); ++k) {
    const PartitionRect rect = partition_rect(motion.partition, k);
    const MacroblockMode mode = motion.modes[k];
    const int first_reference = mode == MacroblockMode::kBackward ? 1 : 0;
    predict_partition(s, mx, my, rect, first_reference, motion.vectors[k][first_reference], &first);
    const bool both = mode == MacroblockMode::kBidirectional;
    if (both) predict_partition(s, mx, my, rect, 1, motion.vectors[k][1], &second);
    // Rounded (or averaged) row by row within the rectangle, per plane.
    auto finish = [&](const int16_t* a, const int16_t* b, uint8_t* dst, int stride, int x, int y, int w, int h) {
      for (int row = y; row < y + h; ++row) {
        const size_t offset = static_cast<size_t>(row) * stride + x;
        if (both) {
          average_prediction(a + offset, b + offset, w, dst + offset);
        } else {
          round_prediction(a + offset, w, dst + offset);
        }
      }
    };
    finish(first.y.data(), second.y.data(), out->y.data(), 16, rect.x, rect.y, rect.width, rect.height);
    finish(first.cb.data(), second.cb.data(), out->cb.data(), 8, rect.x / 2, rect.y / 2, rect.width / 2,
           rect.height / 2);
    finish(first.cr.data(), second.cr.data(), out->cr.data(), 8, rect.x / 2, rect.y / 2, rect.width / 2,
           rect.height / 2);
  }
}

std::array<uint8_t, 2> border_edges_read(const FrameState& s, int mx, int my, const PredictionRecord& record) {
  std::array<uint8_t, 2> edges{};
  if (s.border_mbs == 0 || record.mode == MacroblockMode::kIntra) return edges;
  const int border = 16 * s.border_mbs, x = 16 * reference_mb(s, mx), y = 16 * reference_mb(s, my);
  // Luma blocks in luma samples, chroma blocks in chroma samples, both planes alike.
  auto read = [&](int r, PlaneKind kind, int bx, int by, int w, int h, int vx, int vy) {
    const int padded = kind == PlaneKind::kLuma ? s.references[r]->width : (s.references[r]->width + 1) / 2;
    const int plane_border = kind == PlaneKind::kLuma ? border : border / 2;
    const ReadWindow window = prediction_window(kind, bx, by, w, h, vx, vy);
    edges[r] |=
        border_edges_in_window(padded - 2 * plane_border, plane_border, window.x0, window.y0, window.x1, window.y1);
  };
  auto translate = [&](int r, const PartitionRect& rect, MotionVector v) {
    read(r, PlaneKind::kLuma, x + rect.x, y + rect.y, rect.width, rect.height, v.x, v.y);
    read(r, PlaneKind::kChroma, (x + rect.x) / 2, (y + rect.y) / 2, rect.width / 2, rect.height / 2, v.x, v.y);
  };
  for (int r = 0; r < s.reference_count; ++r) {
    if (record.motion.partition != Partition::k16x16) {
      for (int k = 0; k < partition_count(record.motion.partition); ++k) {
        if (uses_reference(record.motion.modes[k], r))
          translate(r, partition_rect(record.motion.partition, k), record.motion.vectors[k][r]);
      }
    } else if (!uses_reference(record.mode, r)) {
      continue;
    } else if (!record.warp) {
      translate(r, PartitionRect{}, record.vectors[r]);
    } else {
      // The sub-blocks of predict_warp_macroblock (warp_prediction.h).
      const WarpCorners corners = macroblock_corners(s, r, mx, my);
      for (int q = 0; q < 4; ++q) {
        for (int p = 0; p < 4; ++p) {
          const std::array<int, 2> v = warp_subblock_vector(corners, 8 * p + 4, 8 * q + 4);
          read(r, PlaneKind::kLuma, x + 4 * p, y + 4 * q, 4, 4, v[0], v[1]);
          if (p < 2 && q < 2) {
            const std::array<int, 2> c = warp_subblock_vector(corners, 16 * p + 8, 16 * q + 8);
            read(r, PlaneKind::kChroma, x / 2 + 4 * p, y / 2 + 4 * q, 4, 4, c[0], c[1]);
          }
        }
      }
    }
  }
  return edges;
}

bool prediction_leaves_face(const FrameState& s, int mx, int my, MacroblockMode mode, bool warp,
                            const std::array<MotionVector, 2>& vectors) {
  // Sample span in 1/16 pel of the block's pixel centres displaced, plus the one sample
  // interpolation reads beyond it; a warp's extremes lie at its corner pixels, since its
  // vector is bilinear over the block.
  auto outside = [&](int x16, int y16) {
    return x16 < 0 || y16 < 0 || (x16 >> 4) + ((x16 & 15) != 0) >= s.width ||
           (y16 >> 4) + ((y16 & 15) != 0) >= s.height;
  };
  for (int r = 0; r < s.reference_count; ++r) {
    if (!uses_reference(mode, r)) continue;
    for (int k = 0; k < 4; ++k) {
      const int u = (k & 1) * 15, v = (k >> 1) * 15;
      int vx16 = 8 * vectors[r].x, vy16 = 8 * vectors[r].y;
      if (warp) {
        const WarpCorners c = macroblock_corners(s, r, mx, my);
        const int a = 2 * u + 1, b = 2 * v + 1;
        vx16 =
            ((32 - a) * (32 - b) * c[0].x + a * (32 - b) * c[1].x + (32 - a) * b * c[2].x + a * b * c[3].x + 256) >>
            9;
        vy16 =
            ((32 - a) * (32 - b) * c[0].y + a * (32 - b) * c[1].y + (32 - a) * b * c[2].y + a * b * c[3].y + 256) >>
            9;
      }
      if (outside(16 * (16 * mx + u) + vx16, 16 * (16 * my + v) + vy16)) return true;
    }
  }
  return false;
}

void reconstruct_residual_block(const Quantizer& quantizer, const int16_t* levels, const uint8_t* prediction,
                                int prediction_stride, uint8_t* out, int out_stride) {
  int16_t coefficients[kMaxTransformArea];
  dequantize_block(quantizer, levels, coefficients);
  dsp::get_dsp().inverse_transform_add[size_index(quantizer.size)][static_cast<int>(TransformType::kDctDct)](
      coefficients, prediction, prediction_stride, out, out_stride);
}

void copy_macroblock_out(const FrameState& s, int mx, int my, MacroblockPrediction* out) {
  for (int y = 0; y < 16; ++y) {
    std::copy_n(s.planes[0].data() + static_cast<size_t>(16 * my + y) * s.strides[0] + 16 * mx, 16,
                out->y.data() + 16 * y);
  }
  for (int y = 0; y < 8; ++y) {
    const size_t offset = static_cast<size_t>(8 * my + y) * s.strides[1] + 8 * mx;
    std::copy_n(s.planes[1].data() + offset, 8, out->cb.data() + 8 * y);
    std::copy_n(s.planes[2].data() + offset, 8, out->cr.data() + 8 * y);
  }
}

void commit_macroblock(FrameState& s, int mx, int my, const MacroblockInfo& info,
                       const MacroblockPrediction& reconstruction, uint8_t coded_mask) {
  for (int y = 0; y < 16; ++y) {
    std::copy_n(reconstruction.y.data() + 16 * y, 16,
                s.planes[0].data() + static_cast<size_t>(16 * my + y) * s.strides[0] + 16 * mx);
  }
  for (int y = 0; y < 8; ++y) {
    const size_t offset = static_cast<size_t>(8 * my + y) * s.strides[1] + 8 * mx;
    std::copy_n(reconstruction.cb.data() + 8 * y, 8, s.planes[1].data() + offset);
    std::copy_n(reconstruction.cr.data() + 8 * y, 8, s.planes[2].data() + offset);
  }
  for (int b = 0; b < 6; ++b) {
    const int plane = block_plane(b);
    const size_t index = static_cast<size_t>(block_y(b, my)) * s.grid_width(plane) + block_x(b, mx);
    s.coded[plane][index] = static_cast<uint8_t>((coded_mask >> b) & 1);
  }
  if (info.mode != MacroblockMode::kIntra) {
    s.intra_planes[0].mark(16 * mx, 16 * my, TransformSize::k16x16, kDcMode, false);
    s.intra_planes[1].mark(8 * mx, 8 * my, intra::kChromaSize, kDcMode, false);
    s.intra_planes[2].mark(8 * mx, 8 * my, intra::kChromaSize, kDcMode, false);
  }
  s.macroblocks[static_cast<size_t>(my) * s.mbs_x + mx] = info;
}

bool consistent_image(const ImageYCbCr420& image, int width, int height) {
  const size_t chroma = static_cast<size_t>((width + 1) / 2) * static_cast<size_t>((height + 1) / 2);
  return image.width == width && image.height == height &&
         image.y.size() == static_cast<size_t>(width) * static_cast<size_t>(height) && image.cb.size() == chroma &&
         image.cr.size() == chroma;
}

void crop_output(const FrameState& s, ImageYCbCr420* out) {
  copy_planes_to_image({s.planes[0].data(), s.planes[1].data(), s.planes[2].data()}, s.strides, s.width, s.height,
                       out);
}

}  // namespace svc::codec::bframe
