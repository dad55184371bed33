// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/bframe_syntax_writer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "codec/encoder/coefficient_writer.h"

namespace svc::codec {

std::array<float, 4097> make_cost_table() {
  std::array<float, 4097> t{};
  for (int i = 0; i <= 4096; ++i) {
    const double p = std::clamp((i * 8.0 + 4.0) / 32768.0, 1.0 / 32768.0, 1.0);
    t[static_cast<size_t>(i)] = static_cast<float>(-std::log2(p));
  }
  return t;
}

}  // namespace svc::codec

namespace svc::codec::bframe {

void encode_magnitude(RangeEncoder& encoder, MagnitudeBits& bits, unsigned magnitude) {
  const int k = static_cast<int>(std::bit_width(magnitude)) - 1;
  for (int j = 0; j < k; ++j) encoder.encode(bits.above[static_cast<size_t>(j)], 1);
  if (k + 1 < kMagnitudeClasses) encoder.encode(bits.above[static_cast<size_t>(k)], 0);
  if (k > 0) encoder.encode(bits.below[static_cast<size_t>(k - 1)], static_cast<int>((magnitude >> (k - 1)) & 1));
  for (int b = k - 2; b >= 0; --b) encoder.encode_bypass(static_cast<int>((magnitude >> b) & 1));
}

float magnitude_bits(const MagnitudeBits& bits, unsigned magnitude) {
  const int k = static_cast<int>(std::bit_width(magnitude)) - 1;
  float cost = 0;
  for (int j = 0; j < k; ++j) cost += bit_cost(bits.above[static_cast<size_t>(j)], 1);
  if (k + 1 < kMagnitudeClasses) cost += bit_cost(bits.above[static_cast<size_t>(k)], 0);
  if (k > 0) {
    cost += bit_cost(bits.below[static_cast<size_t>(k - 1)], static_cast<int>((magnitude >> (k - 1)) & 1)) +
            static_cast<float>(k - 1);
  }
  return cost;
}

MvdCostTable::MvdCostTable(const SyntaxContexts& c, int component, int context) {
  zero_ = bit_cost(c.mvd_zero[component][context], 0);
  const float flag_and_sign = bit_cost(c.mvd_zero[component][context], 1) + 1;
  for (int k = 0; k < kMagnitudeClasses; ++k) {
    for (unsigned below = 0; below < 2; ++below) {
      // The smallest magnitude of class k with that bit below the leading one.
      const unsigned magnitude = k == 0 ? 1u : (2u + below) << (k - 1);
      class_[static_cast<size_t>(k)][below] = flag_and_sign + magnitude_bits(c.mvd_magnitude[component], magnitude);
    }
  }
}

float mode_bits(const FrameState& s, int mx, int my, MacroblockMode mode) {
  const SyntaxContexts& c = s.contexts;
  float bits = bit_cost(c.skip[skip_context(s, mx, my)], 0);
  bits += bit_cost(c.intra[intra_context(s, mx, my)], mode == MacroblockMode::kIntra);
  if (mode == MacroblockMode::kIntra) return bits;
  return bits + direction_bits(s, mx, my, mode);
}

float direction_bits(const FrameState& s, int mx, int my, MacroblockMode mode) {
  if (s.reference_count == 1) return 0;
  const SyntaxContexts& c = s.contexts;
  const float bits =
      bit_cost(c.bidirectional[bidirectional_context(s, mx, my)], mode == MacroblockMode::kBidirectional);
  if (mode == MacroblockMode::kBidirectional) return bits;
  return bits + bit_cost(c.backward[backward_context(s, mx, my)], mode == MacroblockMode::kBackward);
}

float partition_bits(const FrameState& s, int mx, int my, Partition partition) {
  const SyntaxContexts& c = s.contexts;
  const float split = bit_cost(c.partition_split[partition_context(s, mx, my)], partition != Partition::k16x16);
  if (partition == Partition::k16x16) return split;
  const float quad = bit_cost(c.partition_quad, partition == Partition::k8x8);
  if (partition == Partition::k8x8) return split + quad;
  return split + quad + bit_cost(c.partition_vertical, partition == Partition::k8x16);
}

void encode_partition(RangeEncoder& encoder, FrameState& s, int mx, int my, Partition partition) {
  const SyntaxScope scope(encoder, SyntaxElement::kPartitions);
  SyntaxContexts& c = s.contexts;
  encoder.encode(c.partition_split[partition_context(s, mx, my)], partition != Partition::k16x16);
  if (partition == Partition::k16x16) return;
  encoder.encode(c.partition_quad, partition == Partition::k8x8);
  if (partition != Partition::k8x8) encoder.encode(c.partition_vertical, partition == Partition::k8x16);
}

void encode_direction(RangeEncoder& encoder, FrameState& s, int mx, int my, MacroblockMode mode) {
  if (s.reference_count == 1) return;
  const SyntaxScope scope(encoder, SyntaxElement::kModes);
  SyntaxContexts& c = s.contexts;
  encoder.encode(c.bidirectional[bidirectional_context(s, mx, my)], mode == MacroblockMode::kBidirectional);
  if (mode != MacroblockMode::kBidirectional) {
    encoder.encode(c.backward[backward_context(s, mx, my)], mode == MacroblockMode::kBackward);
  }
}

namespace {

uint32_t signed_code(int32_t value) {
  return value > 0 ? 2 * static_cast<uint32_t>(value) - 1 : 2 * static_cast<uint32_t>(-int64_t{value});
}

}  // namespace

void encode_epipolar_lines(RangeEncoder& encoder, const EpipolarLines& lines) {
  const SyntaxScope scope(encoder, SyntaxElement::kVectors);
  for (const int32_t value : {lines.a, lines.bx, lines.by}) encode_exp_golomb_bypass(encoder, signed_code(value));
}

void encode_mvd_component(RangeEncoder& encoder, SyntaxContexts& c, int component, int context, int value) {
  const SyntaxScope scope(encoder, SyntaxElement::kVectors);
  encoder.encode(c.mvd_zero[component][context], value != 0);
  if (value == 0) return;
  encode_magnitude(encoder, c.mvd_magnitude[component], static_cast<unsigned>(std::abs(value)));
  encoder.encode_bypass(value < 0);
}

float predictor_index_bits(const PredictorIndexBits& bits, int count, int index) {
  if (count < 2) return 0;
  float cost = bit_cost(bits[0], index > 0);
  if (index > 0 && count > 2) cost += bit_cost(bits[1], index > 1);
  return cost;
}

void encode_predictor_index(RangeEncoder& encoder, PredictorIndexBits& bits, int count, int index) {
  if (count < 2) return;
  const SyntaxScope scope(encoder, SyntaxElement::kVectors);
  encoder.encode(bits[0], index > 0);
  if (index > 0 && count > 2) encoder.encode(bits[1], index > 1);
}

float node_component_bits(const SyntaxContexts& c, int component, int kind, int value) {
  const float bits = bit_cost(c.node_zero[component][kind], value != 0);
  if (value == 0) return bits;
  return bits + 1 + magnitude_bits(c.node_magnitude[component][kind], static_cast<unsigned>(std::abs(value)));
}

void encode_node_component(RangeEncoder& encoder, SyntaxContexts& c, int component, int kind, int value) {
  const SyntaxScope scope(encoder, SyntaxElement::kVectors);
  encoder.encode(c.node_zero[component][kind], value != 0);
  if (value == 0) return;
  encoder.encode_bypass(value < 0);
  encode_magnitude(encoder, c.node_magnitude[component][kind], static_cast<unsigned>(std::abs(value)));
}

namespace {

// The prediction kind and the coded difference of node (i, j) towards `reference`
// (docs/codec.md 3.8), the encoder's node value against its prediction.
std::array<int64_t, 2> node_difference(const FrameState& s, int reference, int i, int j,
                                       MotionVector vector_predictor, int* kind) {
  const WarpNode prediction = predict_node(s, reference, i, j, vector_predictor, kind);
  const WarpNode value = s.nodes[reference][s.node_index(i, j)];
  const LineDirection d = node_direction(s, reference, i, j);
  return line_difference(d, to_line_coordinates(value.x, value.y, d),
                         to_line_coordinates(prediction.x, prediction.y, d));
}

}  // namespace

void encode_missing_nodes(RangeEncoder& encoder, FrameState& s, int reference, int mx, int my,
                          MotionVector vector_predictor) {
  for (int k = 0; k < 4; ++k) {
    const int i = corner_i(mx, k), j = corner_j(my, k);
    if (s.known(reference, i, j)) continue;
    int kind = 0;
    const std::array<int64_t, 2> d = node_difference(s, reference, i, j, vector_predictor, &kind);
    encode_node_component(encoder, s.contexts, 0, kind, static_cast<int>(d[0]));
    encode_node_component(encoder, s.contexts, 1, kind, static_cast<int>(d[1]));
    s.node_known[reference][s.node_index(i, j)] = 1;
  }
}

float missing_nodes_bits(FrameState& s, int reference, int mx, int my, MotionVector vector_predictor) {
  float bits = 0;
  std::array<size_t, 4> marked{};
  int marked_count = 0;
  for (int k = 0; k < 4; ++k) {
    const int i = corner_i(mx, k), j = corner_j(my, k);
    if (s.known(reference, i, j)) continue;
    int kind = 0;
    const std::array<int64_t, 2> d = node_difference(s, reference, i, j, vector_predictor, &kind);
    bits += node_component_bits(s.contexts, 0, kind, static_cast<int>(d[0])) +
            node_component_bits(s.contexts, 1, kind, static_cast<int>(d[1]));
    marked[static_cast<size_t>(marked_count++)] = s.node_index(i, j);
    s.node_known[reference][s.node_index(i, j)] = 1;
  }
  for (int m = 0; m < marked_count; ++m) s.node_known[reference][marked[static_cast<size_t>(m)]] = 0;
  return bits;
}

}  // namespace svc::codec::bframe
