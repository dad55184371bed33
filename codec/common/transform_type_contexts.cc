// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/transform_type_contexts.h"

#include "codec/common/cfl.h"
#include "codec/common/intra_prediction.h"

namespace svc::codec {
namespace {

constexpr int kNearAngles = 4;  // modes within this many of horizontal or vertical

}  // namespace

int transform_type_mode_class(int mode) {
  if (mode == kCflMode) return 4;
  if (mode == kPlanarMode || mode == kDcMode) return 0;
  if (mode >= kHorizontalMode - kNearAngles && mode <= kHorizontalMode + kNearAngles) return 1;
  if (mode >= kVerticalMode - kNearAngles && mode <= kVerticalMode + kNearAngles) return 2;
  return 3;
}

}  // namespace svc::codec
