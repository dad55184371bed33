#include "codec/common/transform_type_coder.h"

#include "codec/common/bframe_syntax.h"
#include "codec/common/cfl.h"
#include "codec/common/intra_prediction.h"

namespace svc::codec {
namespace {

constexpr int kNearAngles = 4;  // modes within this many of horizontal or vertical

std::array<AdaptiveBit, 3>& bits_of(TransformTypeContexts& contexts, TransformSize size, int mode) {
  return contexts.bits[static_cast<size_t>(size)][static_cast<size_t>(transform_type_mode_class(mode))];
}

}  // namespace

int transform_type_mode_class(int mode) {
  if (mode == kCflMode) return 4;
  if (mode == kPlanarMode || mode == kDcMode) return 0;
  if (mode >= kHorizontalMode - kNearAngles && mode <= kHorizontalMode + kNearAngles) return 1;
  if (mode >= kVerticalMode - kNearAngles && mode <= kVerticalMode + kNearAngles) return 2;
  return 3;
}

void encode_transform_type(RangeEncoder& encoder, TransformTypeContexts& contexts, TransformSize size, int mode,
                           TransformType type) {
  if (!contexts.enabled) return;
  auto& bits = bits_of(contexts, size, mode);
  const bool vertical = vertical_dst(type);
  encoder.encode(bits[0], vertical);
  encoder.encode(bits[1 + (vertical ? 1 : 0)], horizontal_dst(type));
}

TransformType decode_transform_type(RangeDecoder& decoder, TransformTypeContexts& contexts, TransformSize size,
                                    int mode) {
  if (!contexts.enabled) return TransformType::kDctDct;
  auto& bits = bits_of(contexts, size, mode);
  const bool vertical = decoder.decode(bits[0]) != 0;
  const bool horizontal = decoder.decode(bits[1 + (vertical ? 1 : 0)]) != 0;
  return transform_type_of(vertical, horizontal);
}

float transform_type_bits(const TransformTypeContexts& contexts, TransformSize size, int mode, TransformType type) {
  if (!contexts.enabled) return 0;
  const auto& bits = contexts.bits[static_cast<size_t>(size)][static_cast<size_t>(transform_type_mode_class(mode))];
  const bool vertical = vertical_dst(type);
  return bframe::bit_cost(bits[0], vertical) + bframe::bit_cost(bits[1 + (vertical ? 1 : 0)], horizontal_dst(type));
}

}  // namespace svc::codec
