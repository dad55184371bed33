// SPDX-License-Identifier: BSD-2-Clause
#include "encoder/shard_split.h"

namespace svc {

std::vector<uint32_t> shard_frames(const ContainerIndex& plan, uint32_t shard, uint32_t shard_count) {
  std::vector<uint32_t> intra, predicted;
  for (size_t frame = 0; frame < plan.frames.size(); ++frame) {
    (plan.frames[frame].type == FaceType::kIntra ? intra : predicted).push_back(static_cast<uint32_t>(frame));
  }
  std::vector<uint32_t> frames;
  for (const std::vector<uint32_t>* list : {&intra, &predicted}) {
    const uint64_t size = list->size();
    const size_t begin = static_cast<size_t>(size * (shard - 1) / shard_count);
    const size_t end = static_cast<size_t>(size * shard / shard_count);
    frames.insert(frames.end(), list->begin() + begin, list->begin() + end);
  }
  return frames;
}

}  // namespace svc
