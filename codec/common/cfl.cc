#include "codec/common/cfl.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "codec/common/bframe_syntax.h"
#include "codec/common/dsp/dsp.h"

namespace svc::codec {
namespace {

size_t sign_context(ChromaPlane plane, int cb_alpha) {
  if (plane == ChromaPlane::kCb) return 0;
  return cb_alpha < 0 ? 2 : 1;
}

size_t plane_index(ChromaPlane plane) { return plane == ChromaPlane::kCb ? 0 : 1; }

// Cr's alpha may be 0 (a flag says whether it is); Cb's never is (that block would be
// the DC mode).
void encode_alpha(RangeEncoder& encoder, CflContexts& cfl, ChromaPlane plane, int cb_alpha, int alpha) {
  if (plane == ChromaPlane::kCr) {
    encoder.encode(cfl.cr_nonzero, alpha != 0);
    if (alpha == 0) return;
  }
  encoder.encode(cfl.sign[sign_context(plane, cb_alpha)], alpha < 0);
  auto& magnitude = cfl.magnitude[plane_index(plane)];
  const int m = std::abs(alpha);
  for (int k = 1; k < kCflMaxAlpha; ++k) {
    encoder.encode(magnitude[static_cast<size_t>(k - 1)], m > k);
    if (m == k) break;
  }
}

int decode_alpha(RangeDecoder& decoder, CflContexts& cfl, ChromaPlane plane, int cb_alpha) {
  if (plane == ChromaPlane::kCr && !decoder.decode(cfl.cr_nonzero)) return 0;
  const bool negative = decoder.decode(cfl.sign[sign_context(plane, cb_alpha)]);
  auto& magnitude = cfl.magnitude[plane_index(plane)];
  int m = 1;
  while (m < kCflMaxAlpha && decoder.decode(magnitude[static_cast<size_t>(m - 1)])) ++m;
  return negative ? -m : m;
}

}  // namespace

void encode_chroma_mode(RangeEncoder& encoder, CflContexts& cfl, IntraModeContexts& modes, int cfl_context,
                        const ModeCandidates& candidates, ChromaPlane plane, const ChromaMode& cb,
                        const ChromaMode& mode) {
  if (plane == ChromaPlane::kCr) {
    if (cb.cfl()) encode_alpha(encoder, cfl, plane, cb.alpha, mode.alpha);
    return;
  }
  encoder.encode(cfl.flag[static_cast<size_t>(cfl_context)], mode.cfl());
  if (mode.cfl()) {
    encode_alpha(encoder, cfl, plane, 0, mode.alpha);
  } else {
    encode_intra_mode(encoder, modes, 8, candidates, mode.mode);
  }
}

ChromaMode decode_chroma_mode(RangeDecoder& decoder, CflContexts& cfl, IntraModeContexts& modes, int cfl_context,
                              const ModeCandidates& candidates, ChromaPlane plane, const ChromaMode& cb) {
  ChromaMode mode;
  if (plane == ChromaPlane::kCr) {
    mode.mode = cb.mode;
    if (cb.cfl()) mode.alpha = decode_alpha(decoder, cfl, plane, cb.alpha);
    return mode;
  }
  if (decoder.decode(cfl.flag[static_cast<size_t>(cfl_context)])) {
    mode.mode = kCflMode;
    mode.alpha = decode_alpha(decoder, cfl, plane, 0);
  } else {
    mode.mode = decode_intra_mode(decoder, modes, 8, candidates);
  }
  return mode;
}

float cfl_flag_bits(const CflContexts& cfl, int cfl_context, bool set) {
  return bframe::bit_cost(cfl.flag[static_cast<size_t>(cfl_context)], set);
}

float cfl_alpha_bits(const CflContexts& cfl, ChromaPlane plane, int cb_alpha, int alpha) {
  float bits = 0;
  if (plane == ChromaPlane::kCr) {
    bits += bframe::bit_cost(cfl.cr_nonzero, alpha != 0);
    if (alpha == 0) return bits;
  }
  bits += bframe::bit_cost(cfl.sign[sign_context(plane, cb_alpha)], alpha < 0);
  const auto& magnitude = cfl.magnitude[plane_index(plane)];
  const int m = std::abs(alpha);
  for (int k = 1; k < kCflMaxAlpha; ++k) {
    bits += bframe::bit_cost(magnitude[static_cast<size_t>(k - 1)], m > k);
    if (m == k) break;
  }
  return bits;
}

void cfl_luma_ac(const uint8_t* luma, ptrdiff_t stride, int x0, int y0, int16_t* ac) {
  dsp::get_dsp().cfl_luma_ac_8x8(luma + 2 * y0 * stride + 2 * x0, stride, ac);
}

int dc_prediction_8x8(const uint8_t* edge) {
  uint8_t prediction[64];
  dsp::get_dsp().intra_predict_8x8(edge, kDcMode, prediction);
  return prediction[0];
}

void predict_cfl(const int16_t* ac, int dc, int alpha, uint8_t* out) {
  dsp::get_dsp().cfl_predict_8x8(ac, dc, std::clamp(alpha, -kCflMaxAlpha, kCflMaxAlpha), out);
}

int cfl_least_squares_alpha(const int16_t* ac, const uint8_t* source, ptrdiff_t stride, int dc) {
  int64_t cross = 0, energy = 0;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const int a = ac[8 * y + x];
      cross += a * (source[y * stride + x] - dc);
      energy += a * a;
    }
  }
  if (energy == 0) return 0;
  // prediction - dc = alpha * ac / 32
  const double alpha = 32.0 * static_cast<double>(cross) / static_cast<double>(energy);
  return std::clamp(static_cast<int>(std::lround(alpha)), -kCflMaxAlpha, kCflMaxAlpha);
}

}  // namespace svc::codec
