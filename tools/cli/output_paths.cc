#include "cli/output_paths.h"

#include <string>

namespace svc::cli {

CLI::Validator not_standard_output() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        if (path != "-") return {};
        return "standard output ('-') is not supported: the output must be a named file or folder "
               "(an .svc file needs a seekable file)";
      },
      "PATH");
}

}  // namespace svc::cli
