// SPDX-License-Identifier: BSD-2-Clause
#include "settings_search.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace svc::bench {

SearchTargets default_targets(bool quick) {
  SearchTargets targets;
  if (quick) {
    targets.psnr_y = {32, 38};
    targets.tolerance = 2.0;
    targets.max_runs = 4;
    return targets;
  }
  for (double t = 30; t <= 42.001; t += 2) targets.psnr_y.push_back(t);
  return targets;
}

namespace {

// Linear step from a to b (measured settings) to where PSNR would reach `target`,
// rounded and moved off a and b.
int secant(int a, double pa, int b, double pb, double target) {
  if (std::abs(pb - pa) < 1e-9) return b + (b > a ? 1 : -1);
  return static_cast<int>(std::lround(a + (target - pa) * (b - a) / (pb - pa)));
}

}  // namespace

std::optional<int> next_setting(const SettingRange& range, const std::map<int, double>& measured, double target,
                                double tolerance, int side) {
  if (measured.empty()) return range.seeds.empty() ? range.lowest : range.seeds.front();
  // An end target (side -1 or +1) needs a point at or beyond it, so that the curve spans
  // it, besides one near it; the search aims half the tolerance beyond it.
  bool near = false, reached = side == 0;
  for (const auto& [setting, psnr] : measured) {
    near = near || std::abs(psnr - target) <= tolerance;
    reached = reached || (psnr - target) * side >= 0;
  }
  if (near && reached) return std::nullopt;
  const double aim = target + side * tolerance / 2;
  // A bracket: neighbouring measured settings whose PSNRs lie on both sides of target.
  for (auto it = measured.begin(); std::next(it) != measured.end(); ++it) {
    const auto& [a, pa] = *it;
    const auto& [b, pb] = *std::next(it);
    if ((pa - target) * (pb - target) > 0) continue;
    if (b - a <= 1) return std::nullopt;
    return std::clamp(secant(a, pa, b, pb, aim), a + 1, b - 1);
  }
  // No bracket: go past the end whose PSNR is nearer the target.
  const bool want_higher_psnr = target > std::max(measured.begin()->second, measured.rbegin()->second);
  const bool go_up = want_higher_psnr == range.higher_is_better;
  const auto& [edge, edge_psnr] = go_up ? *measured.rbegin() : *measured.begin();
  const int limit = go_up ? range.highest : range.lowest;
  if (edge == limit) return std::nullopt;
  int step = go_up ? 8 : -8;  // no slope yet: a modest first step
  if (measured.size() >= 2) {
    const auto& [inner, inner_psnr] = go_up ? *std::next(measured.rbegin()) : *std::next(measured.begin());
    step = secant(inner, inner_psnr, edge, edge_psnr, aim) - edge;
    if (go_up) step = std::clamp(step, 1, 32);
    if (!go_up) step = std::clamp(step, -32, -1);
  }
  return go_up ? std::min(edge + step, limit) : std::max(edge + step, limit);
}

Result<std::map<int, double>> search_settings(const SettingRange& range, const SearchTargets& targets,
                                              const MeasureSetting& measure) {
  std::map<int, double> measured;
  int runs = 0;
  auto run = [&](int setting) -> Status {
    SVC_ASSIGN_OR_RETURN(measured[setting], measure(setting));
    ++runs;
    return Status::Ok();
  };
  for (int seed : range.seeds) {
    if (runs < targets.max_runs && !measured.count(seed)) SVC_RETURN_IF_ERROR(run(seed));
  }
  if (range.lowest == range.highest) return measured;
  // The lowest and highest targets are ends: every curve reaches past both (where the
  // codec can), so that any two curves overlap over the whole span of the targets.
  const auto [lowest, highest] = std::minmax_element(targets.psnr_y.begin(), targets.psnr_y.end());
  for (auto target = targets.psnr_y.begin(); target != targets.psnr_y.end(); ++target) {
    const int side = targets.psnr_y.size() < 2 ? 0 : target == lowest ? -1 : target == highest ? 1 : 0;
    while (runs < targets.max_runs) {
      const auto next = next_setting(range, measured, *target, targets.tolerance, side);
      if (!next || measured.count(*next)) break;
      SVC_RETURN_IF_ERROR(run(*next));
    }
  }
  return measured;
}

}  // namespace svc::bench
