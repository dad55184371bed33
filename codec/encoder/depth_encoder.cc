// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/depth_encoder.h"

#include <bit>
#include <cstdlib>

#include "codec/encoder/range_encoder.h"

namespace svc::codec {

namespace {

// Near-lossless quantization: |source - reconstruction| <= max_error (docs/codec.md 8.4).
int32_t quantize_residual(int32_t residual, int max_error, int step) {
  return residual >= 0 ? (residual + max_error) / step : -((max_error - residual) / step);
}

void encode_residual(RangeEncoder& encoder, DepthContexts& contexts, const DepthPixelPrediction& p, int32_t q) {
  const auto inter = static_cast<size_t>(p.inter), activity = static_cast<size_t>(p.activity);
  encoder.encode(contexts.zero[inter][activity], q != 0);
  if (q == 0) return;
  encoder.encode(contexts.sign[inter][activity], q < 0);
  const auto size = static_cast<uint32_t>(std::abs(q));
  const int bits = std::bit_width(size) - 1;
  auto& magnitude = contexts.magnitude[inter][activity];
  for (int i = 0; i < bits; ++i) encoder.encode(magnitude[static_cast<size_t>(i)], 1);
  if (bits < DepthContexts::kMagnitudeBits - 1) encoder.encode(magnitude[static_cast<size_t>(bits)], 0);
  for (int i = bits - 1; i >= 0; --i) encoder.encode_bypass((size >> i) & 1);
}

}  // namespace

std::vector<uint16_t> inverse_depth_codes(const std::vector<float>& eye_z, double near_plane) {
  std::vector<uint16_t> codes(eye_z.size());
  for (size_t i = 0; i < eye_z.size(); ++i) codes[i] = inverse_depth_code(eye_z[i], near_plane);
  return codes;
}

DepthEncodeResult encode_depth(const std::vector<uint16_t>& codes, int width, int height, int max_error,
                               const DepthPrediction* prediction) {
  DepthEncodeResult result;
  result.payload = {kDepthSyntaxVersion, prediction ? kDepthFlagInter : uint8_t{0},
                    static_cast<uint8_t>(max_error)};
  DepthModel model(width, height, max_error, prediction);
  DepthContexts contexts;
  RangeEncoder encoder(&result.payload);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint16_t source = codes[static_cast<size_t>(y) * width + x];
      DepthPixelPrediction p;
      encoder.encode(contexts.background[static_cast<size_t>(model.background_context(x, y))], source == 0);
      if (source == 0) {
        model.record(x, y, 0, p);
        continue;
      }
      p = model.predict(x, y);
      const int32_t q = quantize_residual(int32_t{source} - p.value, max_error, model.step());
      encode_residual(encoder, contexts, p, q);
      model.record(x, y, model.reconstruct(p, q), p);
    }
  }
  encoder.finish();
  result.reconstructed.resize(codes.size());
  model.copy_codes(result.reconstructed.data());
  return result;
}

}  // namespace svc::codec
