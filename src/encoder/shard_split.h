// SPDX-License-Identifier: BSD-2-Clause
// Which faces a shard codes (docs/format.md, "Shards"). Shard k of n (1-based) codes
// the k-th of n even, contiguous runs of the I-faces in frame order and the k-th run of
// the B-faces. Runs in frame order are runs of cells in (y, z, x) order, so a shard's
// B-faces mostly predict from its own I-faces; the few others it codes again.
#pragma once

#include <cstdint>
#include <vector>

#include "container/container.h"

namespace svc {

// The frames of `plan` that shard `shard` (1..shard_count) codes: its I-faces, then its
// B-faces, each in frame order (the order they lie in its part file).
std::vector<uint32_t> shard_frames(const ContainerIndex& plan, uint32_t shard, uint32_t shard_count);

}  // namespace svc
