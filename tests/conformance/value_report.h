// SPDX-License-Identifier: BSD-2-Clause
// Which values the conformance streams give the main syntax elements, as a check that
// the suite reaches every value range (docs/conformance.md, "Values"): I-face quantizer
// indices, flags, luma transform sizes (TransformSize: 0 8x8, 1 4x4, 2 16x16, 3 16x8,
// 4 8x16, 5 16x4, 6 4x16, 7 8x4, 8 4x8), luma and chroma modes, CfL alphas; B-face headers
// (quantizer, filter bank, references, cube border, warp mask, flags) and macroblock
// modes, partitions and warps; the index's depth feature.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "svc/status.h"

namespace svc::conformance {

// Element name -> the values seen.
using ValueTally = std::map<std::string, std::set<int>>;

// Adds the values of every face of `stream`.
Status tally_values(const std::filesystem::path& stream, ValueTally* tally);

// One line an element: its values (runs as ranges) and, where the syntax allows a
// fixed set, the values of it no stream gives.
void print_values(const ValueTally& tally);

}  // namespace svc::conformance
