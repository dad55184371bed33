// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/cell_loader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

namespace svc::viewer {

Result<std::unique_ptr<CellLoader>> CellLoader::open(const std::filesystem::path& path, bool depth) {
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(path));
  if (reader->cells().empty()) return Status(ErrorCode::kBadInput, path.string() + " holds no cells");
  return std::unique_ptr<CellLoader>(new CellLoader(std::move(reader), depth));
}

bool CellLoader::file_has_depth() const { return reader_->info().has_depth; }

glm::dvec3 CellLoader::cell_centre(const CellIndex& cell) const {
  const auto ordinal = reader_->find_cell(cell);
  if (!ordinal) return glm::dvec3(0.0);
  const auto& p = reader_->cells()[*ordinal].position;
  return {p[0], p[1], p[2]};
}

CellIndex CellLoader::cell_for(const glm::dvec3& p) const {
  const std::vector<CellEntry>& cells = reader_->cells();
  if (const auto ordinal = reader_->find_cell_at({p.x, p.y, p.z})) return cells[*ordinal].index;
  // Outside the grid or in a hole: the nearest cell is still the best view there is.
  const auto nearest = std::min_element(cells.begin(), cells.end(), [&](const CellEntry& a, const CellEntry& b) {
    const glm::dvec3 pa(a.position[0], a.position[1], a.position[2]);
    const glm::dvec3 pb(b.position[0], b.position[1], b.position[2]);
    return glm::length(pa - p) < glm::length(pb - p);
  });
  return nearest->index;
}

Status CellLoader::load(const CellIndex& cell, CellImages* out) {
  const auto ordinal = reader_->find_cell(cell);
  if (!ordinal) return Status(ErrorCode::kNotFound, cell_label(cell) + " is not in the file");
  const CellEntry& entry = reader_->cells()[*ordinal];
  const FileInfo& info = reader_->info();
  out->cell = cell;
  out->centre = {entry.position[0], entry.position[1], entry.position[2]};
  out->width = info.face_width;
  out->height = info.face_height;
  std::array<PixelBuffer, kFaceCount> buffers;
  const size_t row_bytes = pixel_row_bytes(PixelFormat::kRGBA8, info.face_width, 0);
  for (int f = 0; f < kFaceCount; ++f) {
    out->cameras[f] = face_camera(entry.cameras[f]);
    out->rgba[f].resize(row_bytes * info.face_height);
    buffers[f].format = PixelFormat::kRGBA8;
    buffers[f].planes[0] = out->rgba[f];
    buffers[f].strides[0] = row_bytes;
    out->depth[f].clear();
  }
  const auto start = std::chrono::steady_clock::now();
  SVC_RETURN_IF_ERROR(reader_->decode_cube_into(cell, buffers));
  if (depth_ && file_has_depth()) SVC_RETURN_IF_ERROR(load_depth(cell, out));
  latencies_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  if (latencies_.size() > kLatencyWindow) latencies_.pop_front();
  ++loads_;
  return Status::Ok();
}

// Into the cell's own planes, which keep their storage from cell to cell.
Status CellLoader::load_depth(const CellIndex& cell, CellImages* out) {
  const auto width = static_cast<size_t>(out->width), height = static_cast<size_t>(out->height);
  for (int f = 0; f < kFaceCount; ++f) {
    std::vector<float>& plane = out->depth[f];
    plane.resize(width * height);
    DepthBuffer buffer;
    buffer.data = plane.data();
    buffer.stride = width * sizeof(float);
    buffer.size = plane.size() * sizeof(float);
    SVC_RETURN_IF_ERROR(reader_->decode_face_depth_into(cell, static_cast<Face>(f), buffer));
  }
  return Status::Ok();
}

Status CellLoader::follow(const glm::dvec3& position, const glm::dvec3& velocity) {
  return reader_->set_viewer(std::array<double, 3>{position.x, position.y, position.z},
                             std::array<double, 3>{velocity.x, velocity.y, velocity.z});
}

double CellLoader::latency_percentile_ms(double q) const {
  if (latencies_.empty()) return 0;
  std::vector<double> sorted(latencies_.begin(), latencies_.end());
  std::sort(sorted.begin(), sorted.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * sorted.size()));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

}  // namespace svc::viewer
