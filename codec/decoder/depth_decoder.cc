// SPDX-License-Identifier: BSD-2-Clause
#include "codec/decoder/depth_decoder.h"

#include <algorithm>
#include <string>

#include "codec/decoder/range_decoder.h"
#include "codec/decoder/syntax_version.h"

namespace svc::codec {

namespace {

int32_t decode_residual(RangeDecoder& decoder, DepthContexts& contexts, const DepthPixelPrediction& p) {
  const auto inter = static_cast<size_t>(p.inter), activity = static_cast<size_t>(p.activity);
  if (decoder.decode(contexts.zero[inter][activity][static_cast<size_t>(p.moved)]) == 0) return 0;
  const int negative = decoder.decode(contexts.sign[inter][static_cast<size_t>(p.signs)]);
  auto& magnitude = contexts.magnitude[inter][activity];
  int bits = 0;
  while (bits < DepthContexts::kMagnitudeBits - 1 && decoder.decode(magnitude[static_cast<size_t>(bits)])) ++bits;
  int32_t size = 1;  // |q|: a leading 1, then `bits` bits
  for (int i = 0; i < bits; ++i) size = (size << 1) | decoder.decode_bypass();
  return negative ? -size : size;
}

}  // namespace

bool depth_payload_is_inter(std::span<const uint8_t> payload) {
  return payload.size() >= kDepthHeaderBytes && (payload[1] & kDepthFlagInter) != 0;
}

Status decode_depth(std::span<const uint8_t> payload, int width, int height,
                    std::span<const DepthReference> references, const Camera& target, uint16_t* codes) {
  if (payload.size() < kDepthHeaderBytes) {
    return Status(ErrorCode::kCorruptData, "depth payload of " + std::to_string(payload.size()) +
                                               " bytes is shorter than its 3-byte header");
  }
  SVC_RETURN_IF_ERROR(check_syntax_version("depth", payload[0], kDepthSyntaxFirst, kDepthSyntaxVersion));
  if ((payload[1] & ~kDepthFlagInter) != 0) {
    return Status(ErrorCode::kCorruptData,
                  "depth flags " + std::to_string(payload[1]) + " at byte 1 set reserved bits");
  }
  const bool inter = (payload[1] & kDepthFlagInter) != 0;
  if (inter && references.empty()) {
    return Status(ErrorCode::kCorruptData, "depth payload is predicted from references, but the face has none");
  }
  DepthPrediction prediction;
  if (inter) predict_depth(references, target, width, height, &prediction);
  DepthModel model(width, height, payload[2], inter ? &prediction : nullptr);
  DepthContexts contexts;
  RangeDecoder decoder(payload.subspan(kDepthHeaderBytes));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      DepthPixelPrediction p;
      if (decoder.decode(contexts.background[static_cast<size_t>(model.background_context(x, y))])) {
        model.record(x, y, 0, p);
        continue;
      }
      p = model.predict(x, y);
      model.record(x, y, model.reconstruct(p, decode_residual(decoder, contexts, p)), p);
    }
  }
  if (decoder.truncated()) {
    return Status(ErrorCode::kCorruptData,
                  "depth payload of " + std::to_string(payload.size()) + " bytes ends before its last pixel");
  }
  model.copy_codes(codes);
  return Status::Ok();
}

}  // namespace svc::codec
