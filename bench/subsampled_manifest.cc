// SPDX-License-Identifier: BSD-2-Clause
// An svc-input manifest over every n-th cell of a database (Figure 7.16's spacing sweep).
#include <fstream>

#include <nlohmann/json.hpp>

#include "bench_util.h"
#include "database/database.h"
#include "svc_bench.h"

namespace svc::bench {

Status write_subsampled_manifest(const std::filesystem::path& db_dir, int step,
                                 const std::filesystem::path& out_dir) {
  if (step < 1)
    return Status(ErrorCode::kInvalidArgument, "subsampling step must be at least 1, not " + std::to_string(step));
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db_dir));
  const std::filesystem::path manifest_path = std::filesystem::is_directory(db_dir) ? db_dir / "manifest.json"
                                                                                    : db_dir;
  std::ifstream in(manifest_path);
  nlohmann::ordered_json doc;
  try {
    in >> doc;
  } catch (const std::exception& e) {
    return Status(ErrorCode::kBadInput, manifest_path.string() + ": " + e.what());
  }
  const auto root = std::filesystem::absolute(manifest.root);
  const std::array<int, 2> axes = horizontal_axes(manifest.up_axis);
  auto absolute = [&](const nlohmann::ordered_json& value) {
    const std::filesystem::path p = value.get<std::string>();
    return p.is_absolute() ? p.string() : (root / p).lexically_normal().string();
  };
  nlohmann::ordered_json cells = nlohmann::ordered_json::array();
  try {
    for (const auto& cell : doc.at("cells")) {
      const auto& index = cell.at("index");
      std::array<int, 3> i{index.at(0).get<int>(), index.at(1).get<int>(), index.at(2).get<int>()};
      if (i[axes[0]] % step != 0 || i[axes[1]] % step != 0) continue;
      i[axes[0]] /= step;
      i[axes[1]] /= step;
      nlohmann::ordered_json copy = cell;
      copy["index"] = i;
      for (auto& [face, entry] : copy.at("faces").items()) {
        (void)face;
        for (const char* key : {"color", "depth"}) {
          if (entry.contains(key)) entry[key] = absolute(entry[key]);
        }
      }
      cells.push_back(std::move(copy));
    }
    if (cells.empty()) {
      return Status(ErrorCode::kInvalidArgument,
                    "subsampling " + db_dir.string() + " every " + std::to_string(step) + " cells leaves no cell");
    }
    auto& grid = doc.at("grid");
    for (int axis : axes) {
      const int dim = grid.at("dims").at(axis).get<int>();
      grid["dims"][axis] = (dim + step - 1) / step;
      grid["spacing"][axis] = grid.at("spacing").at(axis).get<double>() * step;
    }
  } catch (const std::exception& e) {
    return Status(ErrorCode::kBadInput, manifest_path.string() + ": " + e.what());
  }
  doc["cells"] = std::move(cells);
  doc["subsampled_from"] = root.string();
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  std::ofstream out(out_dir / "manifest.json");
  out << doc.dump(1) << "\n";
  out.close();
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + (out_dir / "manifest.json").string());
  return Status::Ok();
}

}  // namespace svc::bench
