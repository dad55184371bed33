// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/rdoq.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "codec/common/dct.h"
#include "codec/encoder/bit_cost.h"
#include "codec/encoder/forward_transform.h"
#include "codec/encoder/quantize.h"

namespace svc::codec {
namespace {

constexpr int kMaxCoefficients = kMaxTransformWidth * kMaxTransformWidth;

float squared_error(const Quantizer& quantizer, const float* coefficients, int position, int level) {
  const float d = coefficients[position] - static_cast<float>(dequantize_level(quantizer, position, level));
  return d * d;
}

// Per scan index: the best level and its cost when the coefficient lies before the end of
// block (with its significance flag) and when it is the last one. Trivial, so that the
// search's table of 256 is not cleared for every block: decide() sets what is read.
struct Decision {
  int level;
  float cost;
  int last_level;
  float last_cost;
  float zero_cost;  // squared error of level 0
};

class RdoqSearch {
 public:
  RdoqSearch(const Quantizer& quantizer, const float* coefficients, const BlockContextSet& contexts, float lambda)
      : quantizer_(quantizer), coefficients_(coefficients), contexts_(contexts), lambda_(lambda) {}

  // Fills decisions_[0..last_scan] in reverse scan order; `rounded` holds the
  // levels rounded to nearest (natural order, signed).
  void decide(const ScanOrder& order, const int16_t* rounded, int last_scan) {
    NeighbourMagnitudes neighbours(order);
    const NeighbourMagnitudes alone(order);
    for (int i = last_scan; i >= 0; --i) {
      const PositionContext& entry = order.scanned[i];
      const int position = entry.position, upper = rounded[position];
      Decision& d = decisions_[static_cast<size_t>(i)];
      d.zero_cost = squared_error(quantizer_, coefficients_, position, 0);
      const int context = neighbours.significance_context(entry);
      d.level = 0;
      d.cost = d.zero_cost + lambda_ * bit_cost(contexts_.significant[context], 0);
      d.last_cost = kInfinity;
      d.last_level = 0;
      const float significant_bits = bit_cost(contexts_.significant[context], 1);
      const int sign = upper < 0 ? -1 : 1;
      for (int magnitude = std::abs(upper); magnitude >= std::max(1, std::abs(upper) - 1); --magnitude) {
        const float error = squared_error(quantizer_, coefficients_, position, sign * magnitude);
        const float cost =
            error + lambda_ * (significant_bits + magnitude_bits(contexts_, neighbours, entry, context, magnitude));
        if (cost < d.cost) {
          d.cost = cost;
          d.level = sign * magnitude;
        }
        const float last_cost =
            error + lambda_ * magnitude_bits(contexts_, alone, entry, last_level_context(entry), magnitude);
        if (last_cost < d.last_cost) {
          d.last_cost = last_cost;
          d.last_level = sign * magnitude;
        }
      }
      neighbours.set(entry, std::abs(d.level));
    }
  }

  // The end of block of least total cost (-1: no level at all), given decide()'s results.
  int choose_last(int last_scan, int coded_block_context, TransformSize size) const {
    float zero_tail = 0;                             // squared error of the positions after the candidate last
    float below = 0;                                 // cost of the positions before it, as decided
    std::array<float, kMaxCoefficients> below_cost;  // set for 0 .. last_scan
    for (int i = 0; i <= last_scan; ++i) {
      below_cost[static_cast<size_t>(i)] = below;
      below += decisions_[static_cast<size_t>(i)].cost;
    }
    float best_cost = kInfinity;
    int best_last = -1;
    if (coded_block_context >= 0) {
      float all_zero = 0;
      for (int i = 0; i <= last_scan; ++i) all_zero += decisions_[static_cast<size_t>(i)].zero_cost;
      best_cost = all_zero + lambda_ * bit_cost(contexts_.coded_block[coded_block_context], 0);
    }
    const float coded_bits = coded_block_context >= 0 ? bit_cost(contexts_.coded_block[coded_block_context], 1)
                                                      : 0.0f;
    const EndOfBlockPricer end_of_block(contexts_, size);
    for (int k = last_scan; k >= 0; --k) {
      const Decision& d = decisions_[static_cast<size_t>(k)];
      if (d.last_cost < kInfinity) {
        const float cost = zero_tail + d.last_cost + below_cost[static_cast<size_t>(k)] +
                           lambda_ * (coded_bits + end_of_block.bits(k));
        if (cost < best_cost) {
          best_cost = cost;
          best_last = k;
        }
      }
      zero_tail += d.zero_cost;
    }
    return best_last;
  }

  const Decision& decision(int scan) const { return decisions_[static_cast<size_t>(scan)]; }

 private:
  static constexpr float kInfinity = 3.0e38f;
  const Quantizer& quantizer_;
  const float* coefficients_;
  const BlockContextSet& contexts_;
  float lambda_;
  std::array<Decision, kMaxCoefficients> decisions_;  // set by decide() for its range
};

int count_nonzero(const int16_t* levels, int count) {
  return static_cast<int>(std::count_if(levels, levels + count, [](int16_t v) { return v != 0; }));
}

// block_levels_bits of levels with `nonzero` non-zero values: without a pass over an
// empty block.
float levels_bits_of(const BlockContextSet& contexts, const int16_t* levels, int nonzero, int coded_block_context,
                     TransformSize size) {
  return nonzero > 0 ? block_levels_bits(contexts, levels, coded_block_context, size)
                     : uncoded_block_bits(contexts, coded_block_context);
}

// quantization_rd_cost, with the bits it priced in *bits.
double rd_cost_and_bits(const Quantizer& quantizer, const float* coefficients, const int16_t* levels,
                        const BlockContextSet& contexts, int coded_block_context, float lambda, float* bits) {
  const ScanOrder& order = scan_order(quantizer.size);
  double error = 0;
  for (int i = 0; i < order.count; ++i) {
    error += squared_error(quantizer, coefficients, order.scan[i], levels[order.scan[i]]);
  }
  *bits = block_levels_bits(contexts, levels, coded_block_context, quantizer.size);
  return error + lambda * *bits;
}

}  // namespace

double quantization_rd_cost(const Quantizer& quantizer, const float* coefficients, const int16_t* levels,
                            const BlockContextSet& contexts, int coded_block_context, float lambda) {
  float bits = 0;
  return rd_cost_and_bits(quantizer, coefficients, levels, contexts, coded_block_context, lambda, &bits);
}

int rdoq_quantize_block(const Quantizer& quantizer, const float* coefficients, const BlockContextSet& contexts,
                        int coded_block_context, float lambda, int16_t* levels, float* levels_bits) {
  const TransformSize size = quantizer.size;
  const ScanOrder& order = scan_order(size);
  const int area = order.count;
  // The levels' count, and their bits where asked for (`known`: already priced).
  auto finish = [&](std::optional<float> known = std::nullopt) {
    const int nonzero = count_nonzero(levels, area);
    if (levels_bits != nullptr)
      *levels_bits = known ? *known : levels_bits_of(contexts, levels, nonzero, coded_block_context, size);
    return nonzero;
  };
  int16_t plain[kMaxCoefficients], rounded[kMaxCoefficients];
  quantize_block(quantizer, coefficients, plain);
  quantize_block_nearest(quantizer, coefficients, rounded);
  std::copy_n(plain, area, levels);
  int last_scan = -1;
  for (int i = order.count - 1; i >= 0 && last_scan < 0; --i) {
    if (rounded[order.scan[i]] != 0) last_scan = i;
  }
  if (last_scan < 0) return finish();

  RdoqSearch search(quantizer, coefficients, contexts, lambda);
  search.decide(order, rounded, last_scan);
  const int chosen_last = search.choose_last(last_scan, coded_block_context, size);
  int16_t optimized[kMaxCoefficients];
  std::copy_n(plain, area, optimized);
  for (int i = 0; i < order.count; ++i) {
    const int level = i < chosen_last    ? search.decision(i).level
                      : i == chosen_last ? search.decision(i).last_level
                                         : 0;
    optimized[order.scan[i]] = static_cast<int16_t>(level);
  }
  // The search's rates are estimates (contexts of neighbours it later dropped); keep
  // plain quantization where it is cheaper by the exact measure.
  if (std::equal(optimized, optimized + area, plain)) return finish();
  float optimized_bits = 0, plain_bits = 0;
  if (rd_cost_and_bits(quantizer, coefficients, optimized, contexts, coded_block_context, lambda, &optimized_bits) <
      rd_cost_and_bits(quantizer, coefficients, plain, contexts, coded_block_context, lambda, &plain_bits)) {
    std::copy_n(optimized, area, levels);
    return finish(optimized_bits);
  }
  return finish(plain_bits);
}

int transform_quantize_block_rd(const Quantizer& quantizer, const int16_t* samples, bool rdoq,
                                const BlockContextSet& contexts, int coded_block_context, float lambda,
                                int16_t* levels, TransformType type, float* levels_bits) {
  if (!rdoq) {
    const int nonzero = transform_quantize_block(quantizer, samples, levels, type);
    if (levels_bits != nullptr)
      *levels_bits = levels_bits_of(contexts, levels, nonzero, coded_block_context, quantizer.size);
    return nonzero;
  }
  const int area = transform_area(quantizer.size);
  float input[kMaxCoefficients], coefficients[kMaxCoefficients];
  for (int i = 0; i < area; ++i) input[i] = samples[i];
  forward_transform(quantizer.size, type, input, coefficients);
  return rdoq_quantize_block(quantizer, coefficients, contexts, coded_block_context, lambda, levels, levels_bits);
}

}  // namespace svc::codec
