// SPDX-License-Identifier: BSD-2-Clause
// Anchors' quality points kept between runs of `svc bench --anchor-cache DIR`: an
// anchor's curve depends on the faces it codes, its settings and the libraries it runs
// on, not on svc, so a corpus run that changes only svc encodes only svc.
//
// An entry is one JSON file named by a hash of its key; the key (a hash of every source
// face's pixels and size, the anchor's plan and options, the quality targets and the
// FFmpeg version) is stored in the file and compared on reading, so a changed input or
// library is a miss, never a stale hit. Entries are written to a temporary file and
// renamed: an interrupted run leaves no half-written entry. A cached anchor has quality
// points only: its speed and random access are not measured.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "anchors.h"
#include "source_faces.h"
#include "svc_bench.h"

namespace svc::bench {

// Hash of the faces as the codecs see them: every pixel, in the manifest's cell order.
std::string source_fingerprint(const SourceFaces& source);

// The full key of `plan` on the faces of `fingerprint` with `quick` targets.
std::string anchor_cache_key(const std::string& fingerprint, const CodecPlan& plan, bool quick);

// The points stored under `key`, or nullopt when there are none (or the entry is
// unreadable, which is a miss too).
std::optional<std::vector<QualityPoint>> load_cached_points(const std::filesystem::path& dir,
                                                            const std::string& key);

// kIoError naming the file when it cannot be written.
Status store_cached_points(const std::filesystem::path& dir, const std::string& key,
                           const std::vector<QualityPoint>& points);

}  // namespace svc::bench
