// The names of the encoder's coding tools: one table, read by --disable-tool and by the
// bench's ablation.
#include <array>

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
};

}  // namespace

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

}  // namespace svc
