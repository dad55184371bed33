// SPDX-License-Identifier: BSD-2-Clause
// Encodes a generated scene with given settings and measures bytes and PSNR-Y over all
// decoded faces, as every benchmark reports svc.
#pragma once

#include "rd_curve.h"
#include "support/scene_cache.h"
#include "svc/encoder.h"

namespace svc::bench {

struct SvcMeasurement {
  RdPoint point;  // setting = qindex; seconds = encode time
  EncodeSummary summary;
};

Result<SvcMeasurement> measure_svc(const SceneFaces& scene, const EncoderSettings& settings);

// measure_svc at each quantizer scale, as an RD curve.
Result<std::vector<SvcMeasurement>> sweep_svc(const SceneFaces& scene, EncoderSettings settings,
                                              const std::vector<int>& qindices);

}  // namespace svc::bench
