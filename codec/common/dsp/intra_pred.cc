// SPDX-License-Identifier: BSD-2-Clause
// Plain intra prediction kernels: the 35 modes of a square (4x4, 8x8, 16x16) or
// rectangular (16x8, 8x16, 16x4, 4x16, 8x4, 4x8) block from its reference edge (planar,
// DC and 33 angles, in the manner of HEVC; docs/codec.md 5.2 is the definition).
#include <algorithm>
#include <cstdlib>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

// Displacement of the projected reference per row (vertical modes) or column
// (horizontal modes), in 1/32 sample, for modes 2..34.
constexpr int kAngle[33] = {32,  26,  21,  17,  13, 9,  5,  2, 0, -2, -5, -9, -13, -17, -21, -26, -32,
                            -26, -21, -17, -13, -9, -5, -2, 0, 2, 5,  9,  13, 17,  21,  26,  32};
// round(256 * 32 / -angle) for the negative angles, indexed by -angle.
int inverse_angle(int angle) {
  switch (angle) {
    case -2: return -4096;
    case -5: return -1638;
    case -9: return -910;
    case -13: return -630;
    case -17: return -482;
    case -21: return -390;
    case -26: return -315;
    default: return -256;  // -32
  }
}

// HEVC's rule (docs/codec.md 5.2): planar always; no angle at 4x4; the three diagonals
// at 8x8; at 16x16 every angle but the three nearest pure horizontal and vertical.
template <int N>
bool edge_is_smoothed(int mode) {
  if (mode == 0) return true;
  const int distance = std::min(std::abs(mode - 26), std::abs(mode - 10));
  return N == 8 ? distance > 7 : N == 16 ? distance > 1 : false;
}

constexpr int log2_of(int n) { return n == 4 ? 2 : n == 8 ? 3 : 4; }

// The edge of an N x H block: 2 (N + H) + 1 samples, the corner at N + H (4N + 1, 2N for
// a square).
template <int N, int H = N>
void smooth_edge(const uint8_t* edge, uint8_t* out) {
  constexpr int kSamples = 2 * (N + H) + 1;
  out[0] = edge[0];
  out[kSamples - 1] = edge[kSamples - 1];
  for (int i = 1; i < kSamples - 1; ++i)
    out[i] = static_cast<uint8_t>((edge[i - 1] + 2 * edge[i] + edge[i + 1] + 2) >> 2);
}

template <int N>
void predict_planar(const uint8_t* edge, uint8_t* out) {
  constexpr int kCorner = 2 * N;
  const uint8_t* above = edge + kCorner + 1;  // above[x], x = 0..2N-1
  const int above_right = above[N], below_left = edge[kCorner - 1 - N];
  for (int y = 0; y < N; ++y) {
    const int left = edge[kCorner - 1 - y];
    for (int x = 0; x < N; ++x) {
      const int sum =
          (N - 1 - x) * left + (x + 1) * above_right + (N - 1 - y) * above[x] + (y + 1) * below_left + N;
      out[N * y + x] = static_cast<uint8_t>(sum >> (log2_of(N) + 1));
    }
  }
}

template <int N>
void predict_dc(const uint8_t* edge, uint8_t* out) {
  constexpr int kCorner = 2 * N;
  int sum = N;
  for (int i = 0; i < N; ++i) sum += edge[kCorner + 1 + i] + edge[kCorner - 1 - i];
  const auto dc = static_cast<uint8_t>(sum >> (log2_of(N) + 1));
  for (int i = 0; i < N * N; ++i) out[i] = dc;
}

// The reference row of an angular mode: main[N + k], k = -N..2N+1, is sample k of the
// projected edge. Returns the angle.
template <int N>
int prepare_angular_reference(const uint8_t* edge, int mode, uint8_t* main) {
  constexpr int kCorner = 2 * N;
  uint8_t smoothed[4 * N + 1];
  if (edge_is_smoothed<N>(mode)) {
    smooth_edge<N>(edge, smoothed);
    edge = smoothed;
  }
  const bool vertical = mode >= 18;
  const int angle = kAngle[mode - 2];
  uint8_t side[2 * N + 1];
  uint8_t* ref = main + N;  // ref[-N .. 2N + 1]
  for (int k = 0; k <= 2 * N; ++k) {
    const int a = edge[kCorner + k], l = edge[kCorner - k];
    ref[k] = static_cast<uint8_t>(vertical ? a : l);
    side[k] = static_cast<uint8_t>(vertical ? l : a);
  }
  ref[2 * N + 1] = 0;  // read, with weight 0, by the steepest angle
  for (int k = -N; k < 0; ++k) ref[k] = 0;
  if (angle < 0) {
    const int last = (N * angle) >> 5;
    // At the mildest angles of a 4x4 block the projection of ref[-1] falls past the
    // side (index 16 of 9); no prediction reads ref[last], so the clamp changes no output.
    for (int k = last; k < 0; ++k) ref[k] = side[std::min((k * inverse_angle(angle) + 128) >> 8, 2 * N)];
  }
  return angle;
}

// Angular modes: the reference along the main direction (above for vertical modes 18..34,
// left for horizontal ones), projected by the angle; transposed for horizontal modes.
template <int N>
void predict_angular(const uint8_t* edge, int mode, uint8_t* out) {
  uint8_t main[3 * N + 2];
  const int angle = prepare_angular_reference<N>(edge, mode, main);
  const uint8_t* ref = main + N;
  const bool vertical = mode >= 18;
  for (int y = 0; y < N; ++y) {
    const int position = (y + 1) * angle;
    const int whole = position >> 5, fraction = position & 31;
    for (int x = 0; x < N; ++x) {
      const int a = ref[x + whole + 1], b = ref[x + whole + 2];
      const int value = ((32 - fraction) * a + fraction * b + 16) >> 5;
      out[vertical ? N * y + x : N * x + y] = static_cast<uint8_t>(value);
    }
  }
}

// HEVC's boundary filters: DC blends its first row and column with the neighbours,
// pure vertical (26) and horizontal (10) add half the edge's gradient to their first
// column or row. N x H blocks (rows of N samples), square by default.
template <int N, int H = N>
void filter_boundary(const uint8_t* edge, int mode, uint8_t* out) {
  constexpr int kCorner = N + H;
  const int corner = edge[kCorner], left = edge[kCorner - 1], above = edge[kCorner + 1];
  if (mode == 1) {
    const int dc = out[N * H - 1];
    out[0] = static_cast<uint8_t>((left + 2 * dc + above + 2) >> 2);
    for (int x = 1; x < N; ++x) out[x] = static_cast<uint8_t>((edge[kCorner + 1 + x] + 3 * dc + 2) >> 2);
    for (int y = 1; y < H; ++y) out[N * y] = static_cast<uint8_t>((edge[kCorner - 1 - y] + 3 * dc + 2) >> 2);
  } else if (mode == 26) {
    for (int y = 0; y < H; ++y)
      out[N * y] = static_cast<uint8_t>(std::clamp(above + ((edge[kCorner - 1 - y] - corner) >> 1), 0, 255));
  } else if (mode == 10) {
    for (int x = 0; x < N; ++x)
      out[x] = static_cast<uint8_t>(std::clamp(left + ((edge[kCorner + 1 + x] - corner) >> 1), 0, 255));
  }
}

template <int N>
void intra_predict(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) {
    uint8_t smoothed[4 * N + 1];
    smooth_edge<N>(edge, smoothed);
    predict_planar<N>(smoothed, out);
    return;
  }
  if (mode == 1) {
    predict_dc<N>(edge, out);
  } else {
    predict_angular<N>(edge, mode, out);
  }
  filter_boundary<N>(edge, mode, out);
}

// Rectangular W x H blocks: the modes of docs/codec.md 5.2 on an edge of W + H samples
// each side, the corner at W + H. The edge is smoothed as for 8x8 blocks (planar and the
// three diagonals).
template <int W, int H>
const uint8_t* rectangular_edge(const uint8_t* edge, int mode, uint8_t* smoothed) {
  if (mode == 1 || !edge_is_smoothed<8>(mode)) return edge;
  smooth_edge<W, H>(edge, smoothed);
  return smoothed;
}

// Planar weighs both directions by the other side's length (as VVC).
template <int W, int H>
void predict_rectangular_planar(const uint8_t* raw_edge, uint8_t* out) {
  constexpr int kCorner = W + H, kLogW = log2_of(W), kLogH = log2_of(H);
  uint8_t smoothed[2 * (W + H) + 1];
  const uint8_t* edge = rectangular_edge<W, H>(raw_edge, 0, smoothed);
  const uint8_t* above = edge + kCorner + 1;
  auto left = [&](int y) { return edge[kCorner - 1 - y]; };
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const int vertical = ((H - 1 - y) * above[x] + (y + 1) * left(H)) << kLogW;
      const int horizontal = ((W - 1 - x) * left(y) + (x + 1) * above[W]) << kLogH;
      out[W * y + x] = static_cast<uint8_t>((vertical + horizontal + W * H) >> (kLogW + kLogH + 1));
    }
  }
}

// DC averages the longer side.
template <int W, int H>
void predict_rectangular_dc(const uint8_t* edge, uint8_t* out) {
  constexpr int kCorner = W + H, kCount = std::max(W, H);
  int sum = 0;
  for (int i = 0; i < kCount; ++i) sum += W > H ? edge[kCorner + 1 + i] : edge[kCorner - 1 - i];
  std::fill_n(out, W * H, static_cast<uint8_t>((sum + kCount / 2) / kCount));
}

// The reference row of an angular mode: main[W + H + k], k = -(W + H)..W + H + 1, is
// sample k of the projected (and, where the mode asks, smoothed) edge; of the negative k
// only those the mode reads are set. Angular modes predict a bw x bh block along its
// columns from it (above for vertical modes, W x H; else the left column, H x W,
// transposed on the way out). Returns the angle.
template <int W, int H>
int prepare_rectangular_reference(const uint8_t* raw_edge, int mode, uint8_t* main) {
  constexpr int kCorner = W + H;
  uint8_t smoothed[2 * (W + H) + 1];
  const uint8_t* edge = rectangular_edge<W, H>(raw_edge, mode, smoothed);
  const bool vertical = mode >= 18;
  const int angle = kAngle[std::max(mode, 2) - 2];  // mode 2..34 (the bound only quiets a warning)
  const int bh = vertical ? H : W;
  uint8_t* ref = main + (W + H);
  ref[W + H + 1] = 0;  // read, with weight 0, by the steepest angle
  uint8_t side[W + H + 1];
  for (int k = 0; k <= W + H; ++k) {
    const int a = edge[kCorner + k], l = edge[kCorner - k];
    ref[k] = static_cast<uint8_t>(vertical ? a : l);
    side[k] = static_cast<uint8_t>(vertical ? l : a);
  }
  if (angle < 0) {
    const int inverse = inverse_angle(angle);
    for (int k = (bh * angle) >> 5; k < 0; ++k) ref[k] = side[std::min((k * inverse + 128) >> 8, W + H)];
  }
  return angle;
}

template <int W, int H>
void predict_rectangular(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) return predict_rectangular_planar<W, H>(edge, out);
  if (mode == 1) {
    predict_rectangular_dc<W, H>(edge, out);
  } else {
    uint8_t main[3 * (W + H) + 2];
    const int angle = prepare_rectangular_reference<W, H>(edge, mode, main);
    const uint8_t* ref = main + (W + H);
    const bool vertical = mode >= 18;
    const int bw = vertical ? W : H, bh = vertical ? H : W;
    for (int y = 0; y < bh; ++y) {
      const int position = (y + 1) * angle, whole = position >> 5, fraction = position & 31;
      for (int x = 0; x < bw; ++x) {
        const int value = ((32 - fraction) * ref[x + whole + 1] + fraction * ref[x + whole + 2] + 16) >> 5;
        out[vertical ? W * y + x : W * x + y] = static_cast<uint8_t>(value);
      }
    }
  }
  filter_boundary<W, H>(edge, mode, out);
}

}  // namespace

void prepare_intra_angular_reference(const uint8_t* edge, int mode, IntraAngularReference* out) {
  out->angle = prepare_angular_reference<8>(edge, mode, out->main);
}

// Calls f.template operator()<W, H>() for the W x H block of `size`.
template <class F>
auto with_block_size(TransformSize size, F&& f) {
  switch (size) {
    case TransformSize::k4x4: return f.template operator()<4, 4>();
    case TransformSize::k16x16: return f.template operator()<16, 16>();
    case TransformSize::k16x8: return f.template operator()<16, 8>();
    case TransformSize::k8x16: return f.template operator()<8, 16>();
    case TransformSize::k16x4: return f.template operator()<16, 4>();
    case TransformSize::k4x16: return f.template operator()<4, 16>();
    case TransformSize::k8x4: return f.template operator()<8, 4>();
    case TransformSize::k4x8: return f.template operator()<4, 8>();
    default: return f.template operator()<8, 8>();
  }
}

int prepare_intra_angular_reference(const uint8_t* edge, int mode, TransformSize size, uint8_t* main) {
  return with_block_size(size, [&]<int W, int H>() {
    if constexpr (W == H) {
      return prepare_angular_reference<W>(edge, mode, main);
    } else {
      return prepare_rectangular_reference<W, H>(edge, mode, main);
    }
  });
}

void filter_intra_boundary(const uint8_t* edge, int mode, TransformSize size, uint8_t* out) {
  with_block_size(size, [&]<int W, int H>() { filter_boundary<W, H>(edge, mode, out); });
}

void smooth_intra_edge(const uint8_t* edge, TransformSize size, uint8_t* out) {
  with_block_size(size, [&]<int W, int H>() { smooth_edge<W, H>(edge, out); });
}

void intra_predict_4x4_c(const uint8_t* edge, int mode, uint8_t* out) { intra_predict<4>(edge, mode, out); }
void intra_predict_8x8_c(const uint8_t* edge, int mode, uint8_t* out) { intra_predict<8>(edge, mode, out); }
void intra_predict_16x16_c(const uint8_t* edge, int mode, uint8_t* out) { intra_predict<16>(edge, mode, out); }
template <int W, int H>
void intra_predict_rectangular_c(const uint8_t* edge, int mode, uint8_t* out) {
  predict_rectangular<W, H>(edge, mode, out);
}
template void intra_predict_rectangular_c<16, 8>(const uint8_t*, int, uint8_t*);
template void intra_predict_rectangular_c<8, 16>(const uint8_t*, int, uint8_t*);
template void intra_predict_rectangular_c<16, 4>(const uint8_t*, int, uint8_t*);
template void intra_predict_rectangular_c<4, 16>(const uint8_t*, int, uint8_t*);
template void intra_predict_rectangular_c<8, 4>(const uint8_t*, int, uint8_t*);
template void intra_predict_rectangular_c<4, 8>(const uint8_t*, int, uint8_t*);

void init_intra_c(DspTable* table) {
  table->intra_predict[size_index(TransformSize::k4x4)] = intra_predict_4x4_c;
  table->intra_predict[size_index(TransformSize::k8x8)] = intra_predict_8x8_c;
  table->intra_predict[size_index(TransformSize::k16x16)] = intra_predict_16x16_c;
  table->intra_predict[size_index(TransformSize::k16x8)] = intra_predict_rectangular_c<16, 8>;
  table->intra_predict[size_index(TransformSize::k8x16)] = intra_predict_rectangular_c<8, 16>;
  table->intra_predict[size_index(TransformSize::k16x4)] = intra_predict_rectangular_c<16, 4>;
  table->intra_predict[size_index(TransformSize::k4x16)] = intra_predict_rectangular_c<4, 16>;
  table->intra_predict[size_index(TransformSize::k8x4)] = intra_predict_rectangular_c<8, 4>;
  table->intra_predict[size_index(TransformSize::k4x8)] = intra_predict_rectangular_c<4, 8>;
}

}  // namespace svc::codec::dsp
