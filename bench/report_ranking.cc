// SPDX-License-Identifier: BSD-2-Clause
// The first table of report.md: the codecs ranked by BD-rate against svc, with each
// anchor's settings and random-access cost, and where svc loses said in words.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "anchors.h"
#include "svc_bench.h"

namespace svc::bench {

namespace {

std::string percent(const std::optional<double>& v) {
  if (!v) return "n/a";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%+.1f%%", *v * 100);
  return buffer;
}

std::string range_text(const std::array<double, 2>& range) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.1f-%.1f dB", range[0], range[1]);
  return buffer;
}

std::string access_text(const AccessStats& a) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.2f (max %d)", a.mean_frames, a.max_frames);
  return buffer;
}

// Codecs with a BD-rate, most efficient first: the reference's BD-rate against a codec is
// larger the better that codec compresses.
std::vector<const CodecResult*> ranked(const BenchResults& r) {
  std::vector<const CodecResult*> rows;
  for (const CodecResult& c : r.codecs) {
    if (c.name == r.bd_reference || c.bd_rate_svc) rows.push_back(&c);
  }
  auto key = [](const CodecResult* c) { return c->bd_rate_svc.value_or(0.0); };
  std::stable_sort(rows.begin(), rows.end(),
                   [&](const CodecResult* a, const CodecResult* b) { return key(a) > key(b); });
  return rows;
}

std::string verdict(const BenchResults& r) {
  std::vector<std::string> losses, wins;
  for (const CodecResult& c : r.codecs) {
    if (!c.bd_rate_svc) continue;
    (*c.bd_rate_svc > 0 ? losses : wins).push_back(c.name + " (" + percent(c.bd_rate_svc) + ")");
  }
  auto join = [](const std::vector<std::string>& items) {
    std::string text;
    for (size_t i = 0; i < items.size(); ++i) text += (i ? ", " : "") + items[i];
    return text;
  };
  const std::string& svc = r.bd_reference;
  if (svc.empty()) {
    std::vector<std::string> layouts;
    for (const std::string& name : all_codec_names()) {
      if (is_svc_layout(name)) layouts.push_back(name);
    }
    return "No svc layout ran (" + join(layouts) + ", with two points): no BD-rate.\n";
  }
  if (losses.empty() && wins.empty()) return "No codec's curve overlaps " + svc + "'s in PSNR-Y: no BD-rate.\n";
  std::string text;
  if (losses.empty()) {
    text = svc + " needs fewer bytes than every anchor here at equal PSNR-Y.";
  } else {
    text =
        "**" + svc + " loses to " + join(losses) + "**: at equal PSNR-Y it needs that many more bytes than each.";
  }
  if (!wins.empty()) text += " " + svc + " is smaller than " + join(wins) + ".";
  return text + "\n";
}

}  // namespace

std::string ranking_markdown(const BenchResults& r) {
  std::ostringstream md;
  const std::string& svc_name = r.bd_reference.empty() ? std::string("svc") : r.bd_reference;
  md << "| rank | codec | BD-rate of " << svc_name << ", PSNR-Y (range) | PSNR-Y " << range_text(kTargetPsnrRange)
     << " (range) | BD-rate of " << svc_name
     << ", PSNR-RGB (range) | settings | frames per random face | points |\n";
  md << "|---:|---|---:|---:|---:|---|---:|---:|\n";
  int rank = 0;
  for (const CodecResult* c : ranked(r)) {
    const bool svc = c->name == r.bd_reference;
    md << "| " << ++rank << " | " << c->name << " | "
       << (svc ? std::string("0 (reference)") : percent(c->bd_rate_svc) + " (" + range_text(c->bd_range_y) + ")")
       << " | "
       << (svc ? std::string("0 (reference)")
               : percent(c->bd_rate_svc_target) +
                     (c->bd_rate_svc_target ? " (" + range_text(c->bd_range_target) + ")" : ""))
       << " | "
       << (svc ? std::string("0 (reference)")
               : percent(c->bd_rate_svc_rgb) + (c->bd_rate_svc_rgb ? " (" + range_text(c->bd_range_rgb) + ")" : ""))
       << " | " << c->description << " | " << access_text(c->access_cold) << " | " << c->points.size() << " |\n";
  }
  md << "\n" << verdict(r);
  return md.str();
}

}  // namespace svc::bench
