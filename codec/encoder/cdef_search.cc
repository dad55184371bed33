// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/cdef_search.h"

#include <algorithm>
#include <bit>
#include <vector>

#include "codec/common/dsp/dsp.h"

namespace svc::codec {
namespace {

using namespace cdef;

// Squared error of the visible part of each filter unit (all three planes) against the source.
std::vector<int64_t> unit_errors(const std::array<PlaneView, 3>& planes, const CdefSource& source) {
  const int units_x = cdef_units(planes[0].width), units_y = cdef_units(planes[0].height);
  std::vector<int64_t> errors(static_cast<size_t>(units_x) * units_y, 0);
  for (int p = 0; p < 3; ++p) {
    const int shift = p == 0 ? 0 : 1;
    const int width = p == 0 ? source.width : (source.width + 1) / 2;
    const int height = p == 0 ? source.height : (source.height + 1) / 2;
    const int unit = kCdefUnitSize >> shift;
    for (int y = 0; y < height; ++y) {
      const uint8_t* a = planes[p].data + static_cast<ptrdiff_t>(y) * planes[p].stride;
      const uint8_t* b = source.planes[p] + static_cast<ptrdiff_t>(y) * source.strides[p];
      int64_t* row = errors.data() + static_cast<size_t>(y / unit) * units_x;
      for (int x = 0; x < width; ++x) {
        const int d = a[x] - b[x];
        row[x / unit] += d * d;
      }
    }
  }
  return errors;
}

// Candidate presets the encoder tries: light to strong, primary only, secondary only, both.
constexpr CdefStrength kCandidates[] = {{0, 1}, {0, 2}, {1, 0}, {2, 0}, {1, 1}, {2, 1},  {3, 1},
                                        {4, 0}, {4, 1}, {4, 2}, {6, 2}, {8, 2}, {10, 3}, {13, 3}};
constexpr int kCandidateCount = static_cast<int>(std::size(kCandidates));

// Rate-distortion cost of a preset set: header bits, then each unit's best choice.
double set_cost(const std::vector<int>& set, const std::vector<std::vector<int64_t>>& errors,
                const std::vector<int64_t>& unfiltered, double lambda, std::vector<uint8_t>* choices) {
  const int n = static_cast<int>(set.size());
  const double index_bits = n > 1 ? std::bit_width(static_cast<unsigned>(n - 1)) : 0;
  double cost = lambda * (2 + 6 * n);
  for (size_t u = 0; u < unfiltered.size(); ++u) {
    double best = static_cast<double>(unfiltered[u]) + lambda;
    uint8_t choice = 0;
    for (int i = 0; i < n; ++i) {
      const double c = static_cast<double>(errors[set[i]][u]) + lambda * (1 + index_bits);
      if (c < best) {
        best = c;
        choice = static_cast<uint8_t>(i + 1);
      }
    }
    cost += best;
    if (choices != nullptr) (*choices)[u] = choice;
  }
  return cost;
}

// A whole N x N block's squared error in a fixed-size loop the compiler vectorizes (64
// squared 8-bit differences fit an int).
template <int N>
int whole_block_error(const uint8_t* block, const uint8_t* source, ptrdiff_t stride) {
  int sum = 0;
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; ++x) {
      const int d = block[y * N + x] - source[y * stride + x];
      sum += d * d;
    }
  }
  return sum;
}

// Squared error of the visible part of a size x size block (size 8 or 4, row stride
// `size`) against the source at (x0, y0) of plane p.
int64_t block_error(const uint8_t* block, int size, const CdefSource& source, int p, int x0, int y0) {
  const int width = p == 0 ? source.width : (source.width + 1) / 2;
  const int height = p == 0 ? source.height : (source.height + 1) / 2;
  const int w = std::min(size, width - x0), h = std::min(size, height - y0);
  if (w == size && h == size) {
    const uint8_t* s = source.planes[p] + static_cast<ptrdiff_t>(y0) * source.strides[p] + x0;
    return size == 8 ? whole_block_error<8>(block, s, source.strides[p])
                     : whole_block_error<4>(block, s, source.strides[p]);
  }
  int64_t sum = 0;
  for (int y = 0; y < h; ++y) {
    const uint8_t* s = source.planes[p] + static_cast<ptrdiff_t>(y0 + y) * source.strides[p] + x0;
    for (int x = 0; x < w; ++x) {
      const int d = block[y * size + x] - s[x];
      sum += d * d;
    }
  }
  return sum;
}

// Per candidate preset, the squared error of every unit filtered with it: block by block
// (each block's direction and bordered samples found once for all candidates), the
// unfiltered error corrected by what filtering changes. Equal to filtering the whole
// frame with each candidate.
std::vector<std::vector<int64_t>> candidate_errors(const std::array<PlaneView, 3>& planes, const CdefSource& source,
                                                   int qindex, std::span<const uint8_t> skip,
                                                   const std::vector<int64_t>& unfiltered, int candidate_step) {
  std::vector<std::vector<int64_t>> errors(kCandidateCount, unfiltered);
  const int blocks_x = planes[0].width / 8, blocks_y = planes[0].height / 8;
  const int units_x = cdef_units(planes[0].width);
  const int damping = damping_of(qindex);
  const dsp::DspTable& dsp = dsp::get_dsp();
  const WidenedPlanes widened(planes);
  for (int by = 0; by < blocks_y; ++by) {
    for (int bx = 0; bx < blocks_x; ++bx) {
      if (!skip.empty() && skip[static_cast<size_t>(by) * blocks_x + bx] != 0) continue;
      if (8 * bx >= source.width || 8 * by >= source.height) continue;  // wholly invisible
      int32_t variance = 0;
      const int direction =
          dsp.cdef_direction_8x8(planes[0].data + static_cast<ptrdiff_t>(8 * by) * planes[0].stride + 8 * bx,
                                 planes[0].stride, &variance);
      uint8_t original[3][64];
      for (int p = 0; p < 3; ++p) {
        const int size = p == 0 ? 8 : 4;
        for (int y = 0; y < size; ++y) {
          std::copy_n(planes[p].data + static_cast<ptrdiff_t>(size * by + y) * planes[p].stride + size * bx, size,
                      original[p] + y * size);
        }
      }
      int64_t before = 0;
      for (int p = 0; p < 3; ++p)
        before += block_error(original[p], p == 0 ? 8 : 4, source, p, p ? 4 * bx : 8 * bx, p ? 4 * by : 8 * by);
      const size_t unit = static_cast<size_t>(by / 8) * units_x + bx / 8;
      for (int c = 0; c < kCandidateCount; c += candidate_step) {
        const CdefStrength& strength = kCandidates[c];
        const int secondary = secondary_of(strength.secondary_code);
        const int luma_direction = strength.primary == 0 ? 0 : direction;
        const dsp::CdefTaps luma_taps{adjusted_primary(strength.primary, variance), secondary, luma_direction,
                                      damping};
        const dsp::CdefTaps chroma_taps{strength.primary, secondary, luma_direction, damping - 1};
        uint8_t filtered[3][64];
        int64_t after = 0;
        for (int p = 0; p < 3; ++p) {
          const int size = p == 0 ? 8 : 4;
          const dsp::CdefTaps& taps = p == 0 ? luma_taps : chroma_taps;
          if (taps.primary == 0 && taps.secondary == 0) {
            std::copy_n(original[p], size * size, filtered[p]);
          } else {
            dsp.cdef_filter_block(widened.at(p, size * bx, size * by), widened.stride(p), filtered[p], size, size,
                                  taps);
          }
          after += block_error(filtered[p], size, source, p, p ? 4 * bx : 8 * bx, p ? 4 * by : 8 * by);
        }
        errors[static_cast<size_t>(c)][unit] += after - before;
      }
    }
  }
  return errors;
}

}  // namespace

void write_cdef_syntax(RangeEncoder& encoder, const CdefParams& params, int units_x, int units_y) {
  const SyntaxScope scope(encoder, SyntaxElement::kFilters);
  const int count = static_cast<int>(params.presets.size());
  for (int bit = 1; bit >= 0; --bit) encoder.encode_bypass(((count - 1) >> bit) & 1);
  for (const CdefStrength& strength : params.presets) {
    for (int bit = 3; bit >= 0; --bit) encoder.encode_bypass((strength.primary >> bit) & 1);
    for (int bit = 1; bit >= 0; --bit) encoder.encode_bypass((strength.secondary_code >> bit) & 1);
  }
  CdefContexts contexts;
  for (int uy = 0; uy < units_y; ++uy) {
    for (int ux = 0; ux < units_x; ++ux) {
      const int preset = params.unit_presets[static_cast<size_t>(uy) * units_x + ux];
      encoder.encode(contexts.unit_on[unit_on_context(params.unit_presets, units_x, ux, uy)], preset != 0);
      if (preset == 0) continue;
      for (int k = 0; k < count - 1; ++k) {
        encoder.encode(contexts.preset_more[k], preset - 1 > k);
        if (preset - 1 == k) break;
      }
    }
  }
}

CdefParams choose_cdef(const std::array<PlaneView, 3>& planes, const CdefSource& source, int qindex,
                       std::span<const uint8_t> skip, double lambda, bool every_candidate) {
  if (!planes_fit(planes) || source.width <= 0 || source.width > planes[0].width || source.height <= 0 ||
      source.height > planes[0].height) {
    return {};
  }
  const int units = cdef_units(planes[0].width) * cdef_units(planes[0].height);
  const std::vector<int64_t> unfiltered = unit_errors(planes, source);
  const int candidate_step = every_candidate ? 1 : 2;
  const std::vector<std::vector<int64_t>> errors =
      candidate_errors(planes, source, qindex, skip, unfiltered, candidate_step);
  // Greedy: add the candidate that lowers the cost most, while one does.
  std::vector<int> set;
  double best_cost = 0;
  for (int64_t e : unfiltered) best_cost += static_cast<double>(e);  // filter off: no bits
  while (set.size() < kCdefMaxPresets) {
    int best_candidate = -1;
    for (int c = 0; c < kCandidateCount; c += candidate_step) {
      if (std::find(set.begin(), set.end(), c) != set.end()) continue;
      std::vector<int> trial = set;
      trial.push_back(c);
      const double cost = set_cost(trial, errors, unfiltered, lambda, nullptr);
      if (cost < best_cost) {
        best_cost = cost;
        best_candidate = c;
      }
    }
    if (best_candidate < 0) break;
    set.push_back(best_candidate);
  }
  CdefParams params;
  if (set.empty()) return params;
  params.unit_presets.resize(static_cast<size_t>(units));
  set_cost(set, errors, unfiltered, lambda, &params.unit_presets);
  for (int c : set) params.presets.push_back(kCandidates[c]);
  return params;
}

}  // namespace svc::codec
