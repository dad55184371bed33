// Rules for where the svc tool may write.
#pragma once

#include <CLI/CLI.hpp>

namespace svc::cli {

// Refuses "-" as an output: the tool writes only to named, seekable files and folders
// (an .svc file is written with its index patched in place, so standard output cannot
// hold one).
CLI::Validator not_standard_output();

}  // namespace svc::cli
