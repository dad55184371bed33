// Plain intra prediction kernels: the 35 modes of an 8x8 block from its reference edge
// (planar, DC and 33 angles, in the manner of HEVC; docs/codec.md 3.1 is the definition)
// and the encoder's 8x8 Hadamard SATD.
#include <cstdlib>

#include "codec/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

constexpr int kSize = 8;
constexpr int kCorner = 16;  // edge[kCorner] is the top-left sample

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

bool edge_is_smoothed(int mode) { return mode == 0 || mode == 2 || mode == 18 || mode == 34; }

void smooth_edge(const uint8_t* edge, uint8_t* out) {
  out[0] = edge[0];
  out[kIntraEdgeSamples - 1] = edge[kIntraEdgeSamples - 1];
  for (int i = 1; i < kIntraEdgeSamples - 1; ++i)
    out[i] = static_cast<uint8_t>((edge[i - 1] + 2 * edge[i] + edge[i + 1] + 2) >> 2);
}

void predict_planar(const uint8_t* edge, uint8_t* out) {
  const uint8_t* above = edge + kCorner + 1;  // above[x], x = 0..15
  const int above_right = above[kSize], below_left = edge[kCorner - 1 - kSize];
  for (int y = 0; y < kSize; ++y) {
    const int left = edge[kCorner - 1 - y];
    for (int x = 0; x < kSize; ++x) {
      const int sum = (kSize - 1 - x) * left + (x + 1) * above_right + (kSize - 1 - y) * above[x] +
                      (y + 1) * below_left + kSize;
      out[kSize * y + x] = static_cast<uint8_t>(sum >> 4);
    }
  }
}

void predict_dc(const uint8_t* edge, uint8_t* out) {
  int sum = kSize;
  for (int i = 0; i < kSize; ++i) sum += edge[kCorner + 1 + i] + edge[kCorner - 1 - i];
  const auto dc = static_cast<uint8_t>(sum >> 4);
  for (int i = 0; i < kSize * kSize; ++i) out[i] = dc;
}

}  // namespace

void prepare_intra_angular_reference(const uint8_t* edge, int mode, IntraAngularReference* out) {
  uint8_t smoothed[kIntraEdgeSamples];
  if (edge_is_smoothed(mode)) {
    smooth_edge(edge, smoothed);
    edge = smoothed;
  }
  const bool vertical = mode >= 18;
  const int angle = kAngle[mode - 2];
  uint8_t side[2 * kSize + 1];
  uint8_t* ref = out->main + kIntraAngularReferenceOffset;  // ref[-kSize .. 2 kSize + 1]
  for (int k = 0; k <= 2 * kSize; ++k) {
    const int a = edge[kCorner + k], l = edge[kCorner - k];
    ref[k] = static_cast<uint8_t>(vertical ? a : l);
    side[k] = static_cast<uint8_t>(vertical ? l : a);
  }
  ref[2 * kSize + 1] = 0;  // read, with weight 0, by the steepest angle
  for (int k = -kSize; k < 0; ++k) ref[k] = 0;
  if (angle < 0) {
    const int last = (kSize * angle) >> 5;
    for (int k = last; k < 0; ++k) ref[k] = side[(k * inverse_angle(angle) + 128) >> 8];
  }
  out->angle = angle;
}

namespace {

// Angular modes: the reference along the main direction (above for vertical modes 18..34,
// left for horizontal ones), projected by the angle; transposed for horizontal modes.
void predict_angular(const uint8_t* edge, int mode, uint8_t* out) {
  IntraAngularReference reference;
  prepare_intra_angular_reference(edge, mode, &reference);
  const uint8_t* ref = reference.main + kIntraAngularReferenceOffset;
  const bool vertical = mode >= 18;
  for (int y = 0; y < kSize; ++y) {
    const int position = (y + 1) * reference.angle;
    const int whole = position >> 5, fraction = position & 31;
    for (int x = 0; x < kSize; ++x) {
      const int a = ref[x + whole + 1], b = ref[x + whole + 2];
      const int value = ((32 - fraction) * a + fraction * b + 16) >> 5;
      out[vertical ? kSize * y + x : kSize * x + y] = static_cast<uint8_t>(value);
    }
  }
}

// 1-D 8-point Hadamard butterflies in place.
void hadamard_8(int* v, int stride) {
  for (int span = 1; span < 8; span *= 2) {
    for (int i = 0; i < 8; i += 2 * span) {
      for (int j = i; j < i + span; ++j) {
        const int a = v[j * stride], b = v[(j + span) * stride];
        v[j * stride] = a + b;
        v[(j + span) * stride] = a - b;
      }
    }
  }
}

}  // namespace

void intra_predict_8x8_c(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) {
    uint8_t smoothed[kIntraEdgeSamples];
    smooth_edge(edge, smoothed);
    predict_planar(smoothed, out);
  } else if (mode == 1) {
    predict_dc(edge, out);
  } else {
    predict_angular(edge, mode, out);
  }
}

int satd_8x8_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int d[64];
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) d[8 * y + x] = source[y * source_stride + x] - prediction[8 * y + x];
  }
  for (int y = 0; y < 8; ++y) hadamard_8(d + 8 * y, 1);
  for (int x = 0; x < 8; ++x) hadamard_8(d + x, 8);
  int sum = 0;
  for (int i = 0; i < 64; ++i) sum += std::abs(d[i]);
  return sum;
}

void init_intra_c(DspTable* table) {
  table->intra_predict_8x8 = intra_predict_8x8_c;
  table->satd_8x8 = satd_8x8_c;
}

}  // namespace svc::codec::dsp
