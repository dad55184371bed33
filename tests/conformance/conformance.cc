// SPDX-License-Identifier: BSD-2-Clause
// svc-conformance MANIFEST [--threads N] [--prefetch] [--no-face-caches] [--values]: decodes every stream the
// manifest lists (tests/conformance/streams.txt: "NAME MD5 what it exercises", streams in streams/NAME.svc beside
// it) and compares the MD5 of its decoded output (stream_digest.h) with the recorded one. Prints one line a stream
// and exits 1 on any mismatch or error. Exits 77 (skipped) when SVC_CPU_MASK asks for a kernel variant this machine
// does not have, so that a test per variant skips where it cannot run.
// --values also prints which values the streams give the main syntax elements
// (value_report.h).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "codec/common/dsp/dsp.h"
#include "conformance/stream_digest.h"
#include "conformance/value_report.h"

namespace svc::conformance {
namespace {

namespace fs = std::filesystem;

struct Entry {
  std::string name;
  std::string md5;
};

std::string flag_names(unsigned flags) {
  using namespace codec::dsp;
  std::string names;
  for (auto [flag, name] :
       {std::pair{kCpuSse2, "sse2"}, {kCpuSse41, "sse4.1"}, {kCpuAvx2, "avx2"}, {kCpuNeon, "neon"}}) {
    if (flags & flag) names += std::string(names.empty() ? "" : " ") + name;
  }
  return names.empty() ? "plain references" : names;
}

// Whether every feature SVC_CPU_MASK names is one this machine has.
bool mask_available() {
  const char* mask = std::getenv("SVC_CPU_MASK");
  if (mask == nullptr || *mask == '\0') return true;
  const unsigned wanted = static_cast<unsigned>(std::strtoul(mask, nullptr, 0));
  return (wanted & ~codec::dsp::detected_cpu_flags()) == 0;
}

bool read_manifest(const fs::path& path, std::vector<Entry>* entries) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Entry entry;
    fields >> entry.name >> entry.md5;
    if (entry.md5.size() != 32) {
      std::fprintf(stderr, "%s: malformed line \"%s\"\n", path.string().c_str(), line.c_str());
      return false;
    }
    entries->push_back(entry);
  }
  return true;
}

int usage() {
  std::fprintf(stderr,
               "usage: svc-conformance MANIFEST [--threads N] [--prefetch] [--no-face-caches] [--values]\n");
  return 2;
}

int run(int argc, char** argv) {
  DecodeSettings settings;
  fs::path manifest;
  bool values = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--threads" && i + 1 < argc) {
      settings.threads = std::atoi(argv[++i]);
    } else if (arg == "--prefetch") {
      settings.prefetch = true;
    } else if (arg == "--no-face-caches") {
      settings.face_caches = false;
    } else if (arg == "--values") {
      values = true;
    } else if (manifest.empty() && arg[0] != '-') {
      manifest = arg;
    } else {
      return usage();
    }
  }
  if (manifest.empty()) return usage();
  if (!mask_available()) {
    std::printf("SVC_CPU_MASK=%s asks for kernels this machine lacks (it has: %s); skipped\n",
                std::getenv("SVC_CPU_MASK"), flag_names(codec::dsp::detected_cpu_flags()).c_str());
    return 77;
  }
  std::vector<Entry> entries;
  if (!read_manifest(manifest, &entries)) {
    std::fprintf(stderr, "cannot read the manifest %s\n", manifest.string().c_str());
    return 2;
  }
  std::printf("kernels: %s; %d decode thread(s)%s%s\n", flag_names(codec::dsp::active_cpu_flags()).c_str(),
              settings.threads, settings.prefetch ? ", prefetch" : "",
              settings.face_caches ? "" : ", references rebuilt from semi-decoded I-faces");
  int failures = 0;
  ValueTally tally;
  for (const Entry& entry : entries) {
    const fs::path stream = manifest.parent_path() / "streams" / (entry.name + ".svc");
    const Result<std::string> md5 = stream_md5(stream, settings);
    if (Status tallied = values ? tally_values(stream, &tally) : Status(); !tallied.ok()) {
      std::printf("FAIL %s: %s\n", entry.name.c_str(), tallied.to_string().c_str());
    } else if (!md5.ok()) {
      std::printf("FAIL %s: %s\n", entry.name.c_str(), md5.status().to_string().c_str());
    } else if (*md5 != entry.md5) {
      std::printf("FAIL %s: MD5 %s, expected %s\n", entry.name.c_str(), md5->c_str(), entry.md5.c_str());
    } else {
      std::printf("ok   %s\n", entry.name.c_str());
      continue;
    }
    ++failures;
  }
  std::printf("%zu streams, %d failed\n", entries.size(), failures);
  if (values) print_values(tally);
  return failures == 0 && !entries.empty() ? 0 : 1;
}

}  // namespace
}  // namespace svc::conformance

int main(int argc, char** argv) { return svc::conformance::run(argc, argv); }
