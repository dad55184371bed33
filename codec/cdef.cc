#include "codec/cdef.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <memory>
#include <vector>

#include "codec/dsp/dsp.h"
#include "codec/thread_buffers.h"

namespace svc::codec {
namespace {

constexpr int kBorder = 2;  // samples read beyond a block on each side

// Contexts of the unit syntax, fresh for every frame.
struct CdefContexts {
  AdaptiveBit unit_on[3];                        // by left + above units on
  AdaptiveBit preset_more[kCdefMaxPresets - 1];  // truncated unary, per position
};

int unit_on_context(const std::vector<uint8_t>& units, int units_x, int ux, int uy) {
  const size_t index = static_cast<size_t>(uy) * units_x + ux;
  return (ux > 0 && units[index - 1] != 0) + (uy > 0 && units[index - units_x] != 0);
}

int damping_of(int qindex) { return 3 + (std::clamp(qindex, 0, 255) >> 6); }
int secondary_of(int code) { return code == 3 ? 4 : code; }

// Primary strength scaled by the block's directional contrast (none on flat blocks).
int adjusted_primary(int primary, int32_t variance) {
  if (variance == 0) return 0;
  const int scale = (variance >> 6) != 0
                        ? std::min(static_cast<int>(std::bit_width(static_cast<uint32_t>(variance >> 6))) - 1, 12)
                        : 0;
  return (primary * (4 + scale) + 8) >> 4;
}

bool planes_fit(const std::array<PlaneView, 3>& planes) {
  const int w = planes[0].width, h = planes[0].height;
  if (planes[0].data == nullptr || w <= 0 || h <= 0 || w % 16 != 0 || h % 16 != 0 || planes[0].stride < w) {
    return false;
  }
  for (int p = 1; p < 3; ++p) {
    if (planes[p].data == nullptr || planes[p].width != w / 2 || planes[p].height != h / 2 ||
        planes[p].stride < w / 2) {
      return false;
    }
  }
  return true;
}

// The planes widened to 16 bits inside a kBorder frame of kCdefUnavailable, so that
// every block's taps read in place, at the plane's edge as well. Each sample is written
// once per frame. The buffers are the calling thread's, kept from frame to frame: a
// fresh allocation of this size costs page faults on every frame.
class WidenedPlanes {
 public:
  explicit WidenedPlanes(const std::array<PlaneView, 3>& planes) {
    for (int p = 0; p < 3; ++p) widen(planes[p], p);
    thread_local ThreadBufferShare share;  // codec/thread_buffers.h
    share.set(capacity_bytes(buffers()[0]) + capacity_bytes(buffers()[1]) + capacity_bytes(buffers()[2]));
  }
  WidenedPlanes(const WidenedPlanes&) = delete;
  WidenedPlanes& operator=(const WidenedPlanes&) = delete;
  const uint16_t* at(int p, int x, int y) const { return buffers()[p].data() + index(p, x, y); }
  int stride(int p) const { return strides_[p]; }

 private:
  // One set per thread; a thread holds one WidenedPlanes at a time.
  static std::array<std::vector<uint16_t>, 3>& buffers() {
    thread_local std::array<std::vector<uint16_t>, 3> samples;
    return samples;
  }
  void widen(const PlaneView& plane, int p) {
    const int stride = plane.width + 2 * kBorder, rows = plane.height + 2 * kBorder;
    strides_[p] = stride;
    std::vector<uint16_t>& buffer = buffers()[p];
    if (buffer.size() < static_cast<size_t>(stride) * rows) buffer.resize(static_cast<size_t>(stride) * rows);
    uint16_t* data = buffer.data();
    std::fill_n(data, static_cast<size_t>(stride) * kBorder, dsp::kCdefUnavailable);
    std::fill_n(data + static_cast<size_t>(stride) * (rows - kBorder), static_cast<size_t>(stride) * kBorder,
                dsp::kCdefUnavailable);
    for (int y = 0; y < plane.height; ++y) {
      uint16_t* row = data + index(p, 0, y);
      std::fill_n(row - kBorder, kBorder, dsp::kCdefUnavailable);
      std::copy_n(plane.data + static_cast<ptrdiff_t>(y) * plane.stride, plane.width, row);
      std::fill_n(row + plane.width, kBorder, dsp::kCdefUnavailable);
    }
  }
  size_t index(int p, int x, int y) const {
    return static_cast<size_t>(y + kBorder) * static_cast<size_t>(strides_[p]) + static_cast<size_t>(x + kBorder);
  }

  std::array<int, 3> strides_{};
};

void filter_block(const WidenedPlanes& input, int p, const PlaneView& output, int x0, int y0, int size,
                  const dsp::CdefTaps& taps) {
  if (taps.primary == 0 && taps.secondary == 0) return;
  dsp::get_dsp().cdef_filter_block(input.at(p, x0, y0), input.stride(p),
                                   output.data + static_cast<ptrdiff_t>(y0) * output.stride + x0, output.stride,
                                   size, taps);
}

// Filters every block of `planes` in place from their unfiltered, widened `input`. The
// direction search reads the block in `planes`: no block is written before its own turn.
void filter_frame(const CdefParams& params, int qindex, std::span<const uint8_t> skip, const WidenedPlanes& input,
                  const std::array<PlaneView, 3>& planes) {
  const int blocks_x = planes[0].width / 8, blocks_y = planes[0].height / 8;
  const int units_x = cdef_units(planes[0].width);
  const int damping = damping_of(qindex);
  for (int by = 0; by < blocks_y; ++by) {
    for (int bx = 0; bx < blocks_x; ++bx) {
      const size_t block = static_cast<size_t>(by) * blocks_x + bx;
      const int preset = params.unit_presets[static_cast<size_t>(by / 8) * units_x + bx / 8];
      if (preset == 0 || (!skip.empty() && skip[block] != 0)) continue;
      const CdefStrength& strength = params.presets[preset - 1];
      const int secondary = secondary_of(strength.secondary_code);
      // Without primary taps the direction is 0 and the contrast unused: no search.
      int32_t variance = 0;
      const int luma_direction =
          strength.primary == 0
              ? 0
              : dsp::get_dsp().cdef_direction_8x8(planes[0].data +
                                                      static_cast<ptrdiff_t>(8 * by) * planes[0].stride + 8 * bx,
                                                  planes[0].stride, &variance);
      filter_block(input, 0, planes[0], 8 * bx, 8 * by, 8,
                   dsp::CdefTaps{adjusted_primary(strength.primary, variance), secondary, luma_direction, damping});
      for (int p = 1; p < 3; ++p) {
        filter_block(input, p, planes[p], 4 * bx, 4 * by, 4,
                     dsp::CdefTaps{strength.primary, secondary, luma_direction, damping - 1});
      }
    }
  }
}

bool params_fit(const CdefParams& params, int units) {
  if (params.presets.empty() || params.presets.size() > kCdefMaxPresets) return false;
  if (params.unit_presets.size() != static_cast<size_t>(units)) return false;
  return std::all_of(params.unit_presets.begin(), params.unit_presets.end(),
                     [&](uint8_t preset) { return preset <= params.presets.size(); });
}

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

int cdef_units(int samples) { return std::max(0, (samples + kCdefUnitSize - 1) / kCdefUnitSize); }

void write_cdef_syntax(RangeEncoder& encoder, const CdefParams& params, int units_x, int units_y) {
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

void read_cdef_syntax(RangeDecoder& decoder, int units_x, int units_y, CdefParams* params) {
  int count = 1;
  for (int bit = 0; bit < 2; ++bit) count += decoder.decode_bypass() << (1 - bit);
  params->presets.assign(static_cast<size_t>(count), CdefStrength{});
  for (CdefStrength& strength : params->presets) {
    int primary = 0, secondary = 0;
    for (int bit = 0; bit < 4; ++bit) primary = (primary << 1) | decoder.decode_bypass();
    for (int bit = 0; bit < 2; ++bit) secondary = (secondary << 1) | decoder.decode_bypass();
    strength = CdefStrength{static_cast<uint8_t>(primary), static_cast<uint8_t>(secondary)};
  }
  params->unit_presets.assign(static_cast<size_t>(units_x) * units_y, 0);
  CdefContexts contexts;
  for (int uy = 0; uy < units_y; ++uy) {
    for (int ux = 0; ux < units_x; ++ux) {
      if (!decoder.decode(contexts.unit_on[unit_on_context(params->unit_presets, units_x, ux, uy)])) continue;
      int preset = 1;
      while (preset < count && decoder.decode(contexts.preset_more[preset - 1])) ++preset;
      params->unit_presets[static_cast<size_t>(uy) * units_x + ux] = static_cast<uint8_t>(preset);
    }
  }
}

void cdef_frame(const CdefParams& params, int qindex, std::span<const uint8_t> skip,
                const std::array<PlaneView, 3>& planes) {
  if (!planes_fit(planes)) return;
  if (!params_fit(params, cdef_units(planes[0].width) * cdef_units(planes[0].height))) return;
  const size_t blocks = static_cast<size_t>(planes[0].width / 8) * (planes[0].height / 8);
  if (!skip.empty() && skip.size() != blocks) return;
  const WidenedPlanes input(planes);
  filter_frame(params, qindex, skip, input, planes);
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
