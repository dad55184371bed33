// SPDX-License-Identifier: BSD-2-Clause
#include "codec/decoder/bframe_syntax_reader.h"

#include <array>
#include <cstdlib>

#include "codec/decoder/coefficient_reader.h"

namespace svc::codec::bframe {

unsigned decode_magnitude(RangeDecoder& decoder, MagnitudeBits& bits) {
  int k = 0;
  while (k + 1 < kMagnitudeClasses && decoder.decode(bits.above[static_cast<size_t>(k)])) ++k;
  if (k == 0) return 1;
  auto magnitude = static_cast<unsigned>(2 + decoder.decode(bits.below[static_cast<size_t>(k - 1)]));
  for (int b = k - 2; b >= 0; --b) magnitude = 2 * magnitude + static_cast<unsigned>(decoder.decode_bypass());
  return magnitude;
}

Partition decode_partition(RangeDecoder& decoder, FrameState& s, int mx, int my) {
  SyntaxContexts& c = s.contexts;
  if (!decoder.decode(c.partition_split[partition_context(s, mx, my)])) return Partition::k16x16;
  if (decoder.decode(c.partition_quad)) return Partition::k8x8;
  return decoder.decode(c.partition_vertical) ? Partition::k8x16 : Partition::k16x8;
}

MacroblockMode decode_direction(RangeDecoder& decoder, FrameState& s, int mx, int my) {
  if (s.reference_count == 1) return MacroblockMode::kForward;
  SyntaxContexts& c = s.contexts;
  if (decoder.decode(c.bidirectional[bidirectional_context(s, mx, my)])) return MacroblockMode::kBidirectional;
  return decoder.decode(c.backward[backward_context(s, mx, my)]) ? MacroblockMode::kBackward
                                                                 : MacroblockMode::kForward;
}

bool decode_epipolar_lines(RangeDecoder& decoder, EpipolarLines* lines) {
  for (int32_t* value : {&lines->a, &lines->bx, &lines->by}) {
    uint32_t code = 0;
    if (!decode_exp_golomb_bypass(decoder, &code) || code > 2 * static_cast<uint32_t>(kMaxEpipolarCoefficient)) {
      return false;
    }
    *value = (code & 1) ? static_cast<int32_t>((code + 1) / 2) : -static_cast<int32_t>(code / 2);
  }
  return true;
}

int decode_mvd_component(RangeDecoder& decoder, SyntaxContexts& c, int component, int context) {
  if (!decoder.decode(c.mvd_zero[component][context])) return 0;
  const auto magnitude = static_cast<int>(decode_magnitude(decoder, c.mvd_magnitude[component]));
  return decoder.decode_bypass() ? -magnitude : magnitude;
}

int decode_predictor_index(RangeDecoder& decoder, PredictorIndexBits& bits, int count) {
  if (count < 2 || !decoder.decode(bits[0])) return 0;
  return count > 2 && decoder.decode(bits[1]) ? 2 : 1;
}

int decode_node_component(RangeDecoder& decoder, SyntaxContexts& c, int component, int kind) {
  if (!decoder.decode(c.node_zero[component][kind])) return 0;
  const bool negative = decoder.decode_bypass() != 0;
  const auto magnitude = static_cast<int>(decode_magnitude(decoder, c.node_magnitude[component][kind]));
  return negative ? -magnitude : magnitude;
}

bool decode_missing_nodes(RangeDecoder& decoder, FrameState& s, int reference, int mx, int my,
                          MotionVector vector_predictor) {
  for (int k = 0; k < 4; ++k) {
    const int i = corner_i(mx, k), j = corner_j(my, k);
    if (s.known(reference, i, j)) continue;
    int kind = 0;
    const WarpNode prediction = predict_node(s, reference, i, j, vector_predictor, &kind);
    const int d0 = decode_node_component(decoder, s.contexts, 0, kind);
    const int d1 = decode_node_component(decoder, s.contexts, 1, kind);
    int64_t x = 0, y = 0;
    add_line_difference(node_direction(s, reference, i, j), prediction.x, prediction.y, {d0, d1}, &x, &y);
    if (std::abs(x) > s.node_limit || std::abs(y) > s.node_limit) return false;
    s.nodes[reference][s.node_index(i, j)] = WarpNode{static_cast<int32_t>(x), static_cast<int32_t>(y)};
    s.node_known[reference][s.node_index(i, j)] = 1;
  }
  return true;
}

}  // namespace svc::codec::bframe
