// SPDX-License-Identifier: BSD-2-Clause
// A quality point as results.json writes it, and read back (svc_bench.h, QualityPoint).
#pragma once

#include <nlohmann/json.hpp>

#include "svc/status.h"
#include "svc_bench.h"

namespace svc::bench {

nlohmann::ordered_json point_json(const QualityPoint& p);

// kBadInput naming the missing or mistyped field.
Result<QualityPoint> point_from_json(const nlohmann::ordered_json& j);

}  // namespace svc::bench
