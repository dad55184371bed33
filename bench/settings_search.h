// SPDX-License-Identifier: BSD-2-Clause
// The quality search of `svc bench`: which settings of a codec to encode so that its
// rate-distortion curve covers the same PSNR-Y targets as every other codec's.
//
// Deterministic: the settings tried depend only on the PSNR each measurement returns.
// PSNR is assumed to move one way with the setting (up with a quality, down with a
// quantizer or CRF). Seeds are measured first; then for each target in turn the search
// brackets it between measured settings and narrows the bracket by secant steps, or
// steps outwards from the nearest measurements when no bracket exists, until a
// measurement lies within `tolerance` of the target, the bracket has no setting left
// inside, the range ends, or `max_runs` measurements were made. The lowest and highest
// targets also need a measurement at or beyond them: each curve spans the targets where
// the codec can reach them, so the curves of any two codecs overlap over that span and
// a BD-rate between them exists.
#pragma once

#include <functional>
#include <map>
#include <vector>

#include "anchors.h"
#include "svc/status.h"

namespace svc::bench {

struct SearchTargets {
  std::vector<double> psnr_y;  // dB
  double tolerance = 0.6;      // dB
  int max_runs = 10;           // measurements per codec, seeds included
};

// 30..42 dB in 2 dB steps (seven targets); quick: 32 and 38 dB, four runs.
SearchTargets default_targets(bool quick);

// Measures one setting and returns its PSNR-Y.
using MeasureSetting = std::function<Result<double>(int setting)>;

// Every setting measured, with its PSNR-Y. The first failure of `measure` is returned.
Result<std::map<int, double>> search_settings(const SettingRange& range, const SearchTargets& targets,
                                              const MeasureSetting& measure);

// The next setting to try for `target` given the measurements so far; nullopt when the
// target is met, cannot be bracketed any closer, or lies beyond the range. A target is
// met by a point within `tolerance` of it; an end target (side -1: the lowest, +1: the
// highest) also needs a point at or beyond it (below the lowest, above the highest).
std::optional<int> next_setting(const SettingRange& range, const std::map<int, double>& measured, double target,
                                double tolerance, int side = 0);

}  // namespace svc::bench
