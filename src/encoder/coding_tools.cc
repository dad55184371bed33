// SPDX-License-Identifier: BSD-2-Clause
// The names of the encoder's coding tools: one table, read by --disable-tool and by the
// bench's ablation.
#include <array>
#include <string>
#include <vector>

#include "svc/encoder.h"

namespace svc {

namespace {

struct CodingToolEntry {
  const char* name;
  bool CodingTools::*enabled;
};

constexpr std::array kCodingTools{
    CodingToolEntry{"warped-prediction", &CodingTools::warped_prediction},
    CodingToolEntry{"sub-pel-refinement", &CodingTools::sub_pel_refinement},
    CodingToolEntry{"intra-directional", &CodingTools::intra_directional},
    CodingToolEntry{"intra-rd-search", &CodingTools::intra_rd_search},
    CodingToolEntry{"quarter-pel", &CodingTools::quarter_pel},
    CodingToolEntry{"visibility-references", &CodingTools::visibility_references},
    CodingToolEntry{"cube-references", &CodingTools::cube_references},
    CodingToolEntry{"deblocking", &CodingTools::deblocking},
    CodingToolEntry{"cdef", &CodingTools::cdef},
    CodingToolEntry{"switchable-filter", &CodingTools::switchable_filter},
    CodingToolEntry{"rdoq", &CodingTools::rdoq},
    CodingToolEntry{"partitions", &CodingTools::partitions},
    CodingToolEntry{"transform-sizes", &CodingTools::transform_sizes},
    CodingToolEntry{"inter-transform-sizes", &CodingTools::inter_transform_sizes},
    CodingToolEntry{"cfl", &CodingTools::cfl},
    CodingToolEntry{"transform-types", &CodingTools::transform_types},
    CodingToolEntry{"b-intra-prediction", &CodingTools::b_intra_prediction},
    CodingToolEntry{"vector-predictors", &CodingTools::vector_predictors},
    CodingToolEntry{"epipolar-lines", &CodingTools::epipolar_lines},
    CodingToolEntry{"full-intra-mode-search", &CodingTools::full_intra_mode_search},
    CodingToolEntry{"b-intra-small-blocks", &CodingTools::b_intra_small_blocks},
    CodingToolEntry{"full-cdef-search", &CodingTools::full_cdef_search},
    CodingToolEntry{"full-inter-split-search", &CodingTools::full_inter_split_search},
    CodingToolEntry{"full-intra-partition-search", &CodingTools::full_intra_partition_search},
    CodingToolEntry{"rdoq-intra-partition-search", &CodingTools::rdoq_intra_partition_search},
    CodingToolEntry{"full-filter-search", &CodingTools::full_filter_search},
    CodingToolEntry{"early-skip", &CodingTools::early_skip},
};

}  // namespace

std::vector<std::string> disabled_coding_tools(const CodingTools& tools) {
  std::vector<std::string> names;
  for (const CodingToolEntry& tool : kCodingTools) {
    if (!(tools.*tool.enabled)) names.emplace_back(tool.name);
  }
  return names;
}

std::vector<std::string> coding_tool_names() {
  std::vector<std::string> names;
  for (const CodingToolEntry& tool : kCodingTools) names.emplace_back(tool.name);
  return names;
}

Status disable_coding_tool(CodingTools* tools, std::string_view name) {
  std::string valid;
  for (const CodingToolEntry& tool : kCodingTools) {
    if (name == tool.name) {
      tools->*tool.enabled = false;
      return Status::Ok();
    }
    valid += valid.empty() ? "" : ", ";
    valid += tool.name;
  }
  return Status(ErrorCode::kInvalidArgument,
                "unknown coding tool '" + std::string(name) + "' (tools: " + valid + ")");
}

namespace {

// What each speed switches off on top of the speed below it, and its layout.
struct EncoderSpeedStep {
  std::vector<const char*> added_tools;
  CubeLayout layout;
};

// The order of the cuts, cheapest in bytes per time saved first (docs/encoder.md 4 and
// docs/bench.md, "Speed settings"): the B-faces' second full pass with another filter
// bank (screened by a cheaper first pass instead), the I-faces' ranking of all 35 modes,
// half the CDEF search and the inter 4x4 trials of blocks without levels; then the
// intra searches' rate-distortion step over modes and transform types and the other
// filter banks; then the visibility layout's planning (it reads every depth file before
// coding) with the references it chooses, and the RDOQ pass of B-face intra macroblocks
// in every partition; then rate-distortion optimized quantization and the B-faces'
// intra blocks under 8x8; last the B-faces' inter partitions.
const std::array<EncoderSpeedStep, kMaxEncoderSpeed + 1> kSpeedSteps = {{
    {{}, CubeLayout::kVisibility},
    {{"full-filter-search", "full-intra-mode-search", "full-cdef-search", "full-inter-split-search"},
     CubeLayout::kVisibility},
    {{"intra-rd-search", "transform-types", "switchable-filter"}, CubeLayout::kVisibility},
    {{"visibility-references", "rdoq-intra-partition-search"}, CubeLayout::kRegular},
    {{"rdoq", "b-intra-small-blocks"}, CubeLayout::kRegular},
    {{"partitions"}, CubeLayout::kRegular},
}};

}  // namespace

std::vector<std::string> speed_disabled_tools(int speed) {
  if (speed < 0 || speed > kMaxEncoderSpeed) return {};
  std::vector<std::string> names;
  for (int step = 1; step <= speed; ++step) {
    for (const char* name : kSpeedSteps[static_cast<size_t>(step)].added_tools) names.emplace_back(name);
  }
  return names;
}

CubeLayout speed_layout(int speed) {
  if (speed < 0 || speed > kMaxEncoderSpeed) return CubeLayout::kVisibility;
  return kSpeedSteps[static_cast<size_t>(speed)].layout;
}

Status apply_encoder_speed(EncoderSettings* settings, int speed) {
  if (speed < 0 || speed > kMaxEncoderSpeed) {
    return Status(ErrorCode::kInvalidArgument,
                  "encoder speed " + std::to_string(speed) + " outside 0.." + std::to_string(kMaxEncoderSpeed));
  }
  CodingTools changed = settings->tools;
  for (const std::string& name : speed_disabled_tools(speed))
    SVC_RETURN_IF_ERROR(disable_coding_tool(&changed, name));
  settings->tools = changed;
  settings->layout = speed_layout(speed);
  return Status::Ok();
}

}  // namespace svc
