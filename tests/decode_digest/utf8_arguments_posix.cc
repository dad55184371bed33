// SPDX-License-Identifier: BSD-2-Clause
#include "decode_digest/utf8_arguments.h"

namespace svc::testing {

std::vector<std::string> utf8_arguments(int argc, char** argv) {
  return std::vector<std::string>(argv, argv + argc);
}

}  // namespace svc::testing
