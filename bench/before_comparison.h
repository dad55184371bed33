// SPDX-License-Identifier: BSD-2-Clause
// svc against the svc of an earlier `svc bench` run (--before): how far the codec moved.
#pragma once

#include <filesystem>
#include <vector>

#include "svc/status.h"
#include "svc_bench.h"

namespace svc::bench {

// svc's points from an earlier results.json (bytes, PSNR-Y, and the B-faces' where the
// run recorded them). Errors: kIoError when unreadable, kInvalidArgument naming the file
// when it is not a results.json with at least two svc points.
Result<std::vector<QualityPoint>> load_svc_points(const std::filesystem::path& results_json);

// BD-rates of `now` against `before`; the B-face one only when both record B-faces.
BeforeComparison compare_with_before(const std::filesystem::path& results_json,
                                     const std::vector<QualityPoint>& before, const std::vector<QualityPoint>& now);

}  // namespace svc::bench
