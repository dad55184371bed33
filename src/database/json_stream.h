// SPDX-License-Identifier: BSD-2-Clause
// Reading a large JSON document as a stream: the values outside one top-level array make
// a small document of their own, and each element of that array is built alone, handed
// over with where it lies in the file, and dropped. The manifest of a database of any
// size is read this way (manifest.cc).
//
// Error behaviour: nothing here throws; syntax errors come back with their position.
// Threading: no shared state; each call reads its own stream.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "svc/status.h"

namespace svc {

// The first syntax error of a streamed document.
struct JsonSyntaxError {
  std::string message;        // nlohmann::json's; it names line and column when has_position
  bool has_position = false;  // false for a number too large for a double
  uint64_t offset = 0;        // bytes read when the error was found
  std::string last_token;
};

// What a streamed read of `file` saw.
struct StreamedJson {
  // The document without the streamed array's elements (the array itself stays, empty).
  nlohmann::json outline;
  int array_count = 0;           // top-level arrays under the streamed key (JSON allows repeats)
  uint64_t last_array_size = 0;  // elements of the last of them
  bool syntax_ok = true;
  JsonSyntaxError syntax_error;
  bool stopped = false;  // `element` returned false
};

// Called for each element of the streamed array: the element, its byte offset and size in
// the file (exact for objects and arrays, the braces included). Returning false stops the
// read.
using JsonElementHandler = std::function<bool(nlohmann::json& element, uint64_t offset, uint64_t size)>;

// Reads `in` (opened on the file, binary) once. The top-level array under `array_key` in
// the root object whose ordinal among such arrays is `streamed_array` (1-based; 0 for
// none) has its elements handed to `element`; the elements of every such array are left
// out of `outline`. The document held at once is `outline` and one element.
StreamedJson stream_json(std::istream& in, const std::string& array_key, int streamed_array,
                         const JsonElementHandler& element);

// 1-based line and column of byte `offset` of the file `in` reads (from its start).
std::pair<uint64_t, uint64_t> line_and_column(std::istream& in, uint64_t offset);

}  // namespace svc
