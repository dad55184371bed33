// SPDX-License-Identifier: BSD-2-Clause
// What ties a part file to its database and settings (docs/format.md, "Shards").
#pragma once

#include <cstdint>
#include <filesystem>

#include <string>

#include "database/database.h"
#include "svc/encoder.h"
#include "svc/status.h"

namespace svc {

// The version of svc that writes and merges part files; parts of another are refused.
extern const char* const kSvcVersion;

// A 64-bit FNV-1a hash of the manifest file's bytes and of the path and size of every
// file its faces name. Contents are not read: a changed image of the same size is not
// noticed (hashing would read the whole database once per shard).
Result<uint64_t> database_fingerprint(const std::filesystem::path& db_dir, const DatabaseManifest& manifest);

// The encoder settings that change a part's bytes but are not in its plan, as the
// command-line options that give them ("--disable-tool rdoq --b-qindex-offset 30"; empty
// for the defaults): the coding tools switched off, in coding_tool_names() order, the
// I-faces' quantization matrix and a fixed B-face quantizer offset. The merge refuses
// parts whose texts differ.
std::string shard_settings_text(const EncoderSettings& settings);

}  // namespace svc
