// SPDX-License-Identifier: BSD-2-Clause
// How a database lays out its cells and depths: shared by svc-input manifests
// (docs/input-format.md) and the .svc index (docs/format.md).
#pragma once

#include <array>
#include <cstdint>

namespace svc {

enum class DepthMode : uint8_t { kEyeZ = 0, kRadial = 1 };
enum class UpAxis : uint8_t { kX = 0, kY = 1, kZ = 2 };

struct GridSpec {
  std::array<int32_t, 3> dims{1, 1, 1};
  std::array<double, 3> origin{0, 0, 0};
  std::array<double, 3> spacing{1, 1, 1};
};

}  // namespace svc
