// SPDX-License-Identifier: BSD-2-Clause
// The B-face motion search: vectors by SAD plus vector bits (docs/encoder.md).
#include "codec/encoder/bframe_macroblock_coder.h"

#include <cstdlib>

#include "codec/common/dsp/dsp.h"
#include "codec/encoder/sad.h"

namespace svc::codec::bframe {

int sad_rect(const uint8_t* source, int source_stride, const uint8_t* prediction, const PartitionRect& rect) {
  int sum = 0;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
      sum += std::abs(static_cast<int>(source[y * source_stride + x]) - static_cast<int>(prediction[16 * y + x]));
    }
  }
  return sum;
}

CandidateList partition_candidates(const MacroblockHints& hints, const PartitionRect& rect, size_t limit,
                                   VectorSet& listed) {
  listed.clear();
  std::array<const CandidateList*, 4> lists{};
  int count = 0;
  for (int b = 0; b < 4; ++b) {
    const int x = 8 * (b & 1), y = 8 * (b >> 1);
    if (x < rect.x || y < rect.y || x >= rect.x + rect.width || y >= rect.y + rect.height) continue;
    if (hints.blocks[b] != nullptr) lists[count++] = hints.blocks[b];
  }
  if (count == 0) {
    if (hints.macroblock == nullptr) return {};
    const CandidateList& list = *hints.macroblock;
    CandidateList first(list.begin(), list.begin() + static_cast<ptrdiff_t>(std::min(limit, list.size())));
    for (const MotionVector& v : first) listed.insert(v);
    return first;
  }
  CandidateList merged;
  for (size_t rank = 0;; ++rank) {
    bool any = false;
    for (int l = 0; l < count; ++l) {
      if (rank >= lists[l]->size()) continue;
      any = true;
      const MotionVector v = (*lists[l])[rank];
      if (listed.insert(v)) merged.push_back(v);
      if (merged.size() >= limit) return merged;
    }
    if (!any) return merged;
  }
}

bool motion_varies(const MacroblockHints& hints) {
  const CandidateList* first = nullptr;
  for (const CandidateList* list : hints.blocks) {
    if (list == nullptr || list->empty()) continue;
    if (first != nullptr && list->front() != first->front()) return true;
    first = list;
  }
  return first == nullptr && hints.macroblock != nullptr && hints.macroblock->size() > 1;
}

float BFrameMacroblockCoder::vector_bits(int reference, MotionVector vector) const {
  return vector_bits(reference, vector, predictor_lists_[reference]);
}

float BFrameMacroblockCoder::vector_bits(int reference, MotionVector vector,
                                         const VectorPredictors& predictors) const {
  return vector_bits(vector, line_predictors(reference, predictors));
}

float BFrameMacroblockCoder::vector_bits(MotionVector vector, const LinePredictors& predictors) const {
  float bits = 0;
  cheapest_predictor(vector, predictors, &bits);
  return bits;
}

LinePredictors BFrameMacroblockCoder::line_predictors(int reference, const VectorPredictors& predictors) const {
  LinePredictors out;
  out.count = predictors.count;
  out.usable = usable_predictors(predictors.count);
  out.line = macroblock_direction(s_, reference, mx_, my_);
  for (int i = 0; i < out.usable; ++i) {
    const MotionVector p = predictors.vectors[static_cast<size_t>(i)];
    out.coordinates[static_cast<size_t>(i)] = to_line_coordinates(p.x, p.y, out.line);
  }
  return out;
}

int BFrameMacroblockCoder::cheapest_predictor(MotionVector vector, const LinePredictors& predictors,
                                              float* bits) const {
  int best = 0;
  const LineDirection line = predictors.line;
  const LineCoordinates coordinates = to_line_coordinates(vector.x, vector.y, line);
  for (int i = 0; i < predictors.usable; ++i) {
    const std::array<int64_t, 2> d =
        line_difference(line, coordinates, predictors.coordinates[static_cast<size_t>(i)]);
    const float candidate = predictor_index_bits(s_.contexts.predictor_index, predictors.count, i) +
                            mvd_costs_[0].bits(static_cast<int>(d[0])) + mvd_costs_[1].bits(static_cast<int>(d[1]));
    if (i == 0 || candidate < *bits) {
      best = i;
      *bits = candidate;
    }
  }
  return best;
}

int BFrameMacroblockCoder::usable_predictors(int count) const { return vector_predictors_ ? count : 1; }

int BFrameMacroblockCoder::rect_sad(int reference, const PartitionRect& rect, MotionVector v) const {
  const uint8_t* source = source_.planes[0].data() + static_cast<size_t>(16 * my_) * source_.strides[0] + 16 * mx_;
  if (search_[reference] != nullptr) {
    const int sad = search_[reference]->sad(source + rect.y * source_.strides[0] + rect.x, source_.strides[0],
                                            16 * reference_mb(s_, mx_) + rect.x,
                                            16 * reference_mb(s_, my_) + rect.y, rect.width, rect.height, v);
    if (sad >= 0) return sad;
  }
  const ImageYCbCr420& ref = *s_.references[reference];
  if (rect.width == 16 && rect.height == 16) {
    return sad_macroblock_luma(ref, reference_mb(s_, mx_), reference_mb(s_, my_), v, source, source_.strides[0],
                               s_.filter);
  }
  int16_t intermediate[256];
  uint8_t prediction[256];
  predict_block(ref.y.data(), ref.width, ref.height, PlaneKind::kLuma, 16 * reference_mb(s_, mx_) + rect.x,
                16 * reference_mb(s_, my_) + rect.y, rect.width, rect.height, v.x, v.y,
                intermediate + 16 * rect.y + rect.x, 16, s_.filter);
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    round_prediction(intermediate + 16 * y + rect.x, rect.width, prediction + 16 * y + rect.x);
  }
  return sad_rect(source, source_.strides[0], prediction, rect);
}

MotionVector BFrameMacroblockCoder::clamp_vector(MotionVector v) const {
  auto component = [&](int c) {
    if (!quarter_pel_ && (c & 1) != 0) c += c > 0 ? 1 : -1;
    const int limit = quarter_pel_ ? s_.vector_limit : s_.vector_limit & ~1;
    return static_cast<int16_t>(std::clamp(c, -limit, limit));
  };
  return MotionVector{component(v.x), component(v.y)};
}

MotionVector BFrameMacroblockCoder::search_reference(int reference, const PartitionRect& rect,
                                                     const VectorPredictors& predictors,
                                                     std::span<const MotionVector> list, BFrameStats* stats) {
  tried_.clear();
  MotionVector best = predictors.vectors[0];
  double best_cost = 1e300;
  const LinePredictors priced = line_predictors(reference, predictors);
  auto try_vector = [&](MotionVector v) {
    v = clamp_vector(v);
    if (!tried_.insert(v)) return false;
    const double rate = lambda_sad_ * vector_bits(v, priced);
    if (rate >= best_cost) return true;  // cannot win whatever its SAD
    const int sad = rect_sad(reference, rect, v);
    if (stats != nullptr) ++stats->sad_evaluations;
    const double cost = sad + rate;
    if (cost < best_cost) {
      best_cost = cost;
      best = v;
    }
    return true;
  };
  int supplied = 0;
  // Lists are ranked (most pixels first): the tail rarely wins and costs a SAD each.
  const size_t count = std::min(list.size(), static_cast<size_t>(max_candidates_));
  // A candidate is the motion of one pixel; on the line through the centre it predicts
  // a surface facing the camera as well or better, and costs no across difference.
  const LineDirection line = macroblock_direction(s_, reference, mx_, my_);
  for (size_t k = 0; k < count; ++k) {
    supplied += try_vector(list[k]);
    if (s_.lines[reference].present()) try_vector(onto_line(line, list[k], s_.vector_limit));
  }
  if (stats != nullptr && rect.width == 16 && rect.height == 16) stats->candidates_evaluated += supplied;
  if (supplied == 0) try_vector(MotionVector{});
  for (int i = 0; i < usable_predictors(predictors.count); ++i)
    try_vector(predictors.vectors[static_cast<size_t>(i)]);
  if (refine_) {
    // The half-pel ring around the best, then the quarter-pel ring around the new best.
    for (int step = 2; step >= (quarter_pel_ ? 1 : 2); --step) {
      const MotionVector centre = best;
      for (int dy = -step; dy <= step; dy += step) {
        for (int dx = -step; dx <= step; dx += step) {
          if (dx != 0 || dy != 0) {
            try_vector(MotionVector{static_cast<int16_t>(centre.x + dx), static_cast<int16_t>(centre.y + dy)});
          }
        }
      }
    }
  }
  return best;
}

}  // namespace svc::codec::bframe
