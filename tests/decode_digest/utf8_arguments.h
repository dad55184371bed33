// SPDX-License-Identifier: BSD-2-Clause
// The program's arguments as UTF-8, as the C API takes paths.
#pragma once

#include <string>
#include <vector>

namespace svc::testing {

// Linux passes the bytes as given (UTF-8 in a UTF-8 locale); on Windows main's argv is
// in the ANSI code page, so the arguments come from the UTF-16 command line instead.
std::vector<std::string> utf8_arguments(int argc, char** argv);

}  // namespace svc::testing
