#include "svc/reader.h"

#include <cmath>
#include <unordered_map>

#include "codec/bframe_codec.h"
#include "codec/color.h"
#include "codec/frame_codec.h"
#include "common/file_io.h"
#include "container/container.h"

namespace svc {

namespace {

std::string cell_face_name(const CellIndex& c, Face face) {
  return "cell (" + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) +
         ") face " + face_name(face);
}

uint64_t cell_key(const CellIndex& c) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(c.y)) << 42) ^
         (static_cast<uint64_t>(static_cast<uint32_t>(c.z)) << 21) ^ static_cast<uint32_t>(c.x);
}

}  // namespace

struct Reader::Impl {
  std::unique_ptr<ReadOnlyFile> file;
  ReaderSettings settings;
  ContainerIndex index;
  FileInfo info;
  std::vector<CellEntry> cells;
  std::unordered_map<uint64_t, size_t> cell_by_key;
  std::array<bool, 2> slot_damaged{false, false};

  std::string frame_name(uint32_t frame) const {
    const FrameRecord& record = index.frames[frame];
    return cell_face_name(index.cells[record.cell].index, record.face);
  }

  Result<std::vector<uint8_t>> read_payload(uint32_t frame) const {
    return read_frame_payload(*file, index.frames[frame], frame_name(frame));
  }

  Result<ImageYCbCr420> decode_frame(uint32_t frame) const {
    const FrameRecord& record = index.frames[frame];
    SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, read_payload(frame));
    ImageYCbCr420 image;
    if (record.kind == FrameKind::kIntra) {
      Status status = codec::decode_intra_frame(payload, static_cast<int>(index.face_width),
                                                static_cast<int>(index.face_height), &image);
      if (!status.ok()) {
        return status.with_context(file->path().string() + ": " + frame_name(frame) + " (chunk at byte offset " +
                                   std::to_string(record.chunk_offset) + ")");
      }
      return image;
    }
    std::array<ImageYCbCr420, 2> refs;
    for (size_t r = 0; r < record.references.size(); ++r) {
      // References are I-faces (checked when the index was read): no recursion beyond one level.
      auto ref = decode_frame(record.references[r]);
      if (!ref.ok()) {
        return ref.status().with_context(frame_name(frame) + " cannot be decoded: its reference");
      }
      refs[r] = std::move(ref).value();
    }
    Status status = codec::decode_b_frame(payload, static_cast<int>(index.face_width),
                                          static_cast<int>(index.face_height), refs[0],
                                          record.references.size() > 1 ? &refs[1] : nullptr, &image, nullptr);
    if (!status.ok()) {
      return status.with_context(file->path().string() + ": " + frame_name(frame) + " (chunk at byte offset " +
                                 std::to_string(record.chunk_offset) + ")");
    }
    return image;
  }

  Result<uint32_t> frame_of(const CellIndex& cell, Face face) const {
    const auto it = cell_by_key.find(cell_key(cell));
    if (it == cell_by_key.end() || static_cast<unsigned>(face) >= kFaceCount) {
      return Status(ErrorCode::kNotFound, file->path().string() + " has no " + cell_face_name(cell, face));
    }
    return static_cast<uint32_t>(it->second * kFaceCount + static_cast<unsigned>(face));
  }
};

ReaderSettings default_reader_settings() { return ReaderSettings{}; }

Reader::Reader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Reader::~Reader() = default;

Result<std::unique_ptr<Reader>> Reader::open(const std::filesystem::path& path, const ReaderSettings& settings) {
  auto impl = std::make_unique<Impl>();
  impl->settings = settings;
  SVC_ASSIGN_OR_RETURN(impl->file, ReadOnlyFile::open(path));
  SVC_ASSIGN_OR_RETURN(OpenedContainer opened, open_container(*impl->file, settings.limits));
  impl->index = std::move(opened.index);
  impl->slot_damaged = opened.slot_damaged;
  const ContainerIndex& index = impl->index;

  FileInfo& info = impl->info;
  info.format_major = kFormatMajor;
  info.format_minor = kFormatMinor;
  info.file_bytes = impl->file->size();
  info.face_width = static_cast<int>(index.face_width);
  info.face_height = static_cast<int>(index.face_height);
  info.grid_dims = index.grid.dims;
  info.grid_origin = index.grid.origin;
  info.grid_spacing = index.grid.spacing;
  info.quality = static_cast<int>(index.coding.quality);
  info.quant_scale = static_cast<int>(index.coding.quant_scale);
  info.i_spacing = index.coding.i_spacing;
  info.motion = index.coding.motion == MotionSource::kDepth ? "depth" : "logarithmic";
  info.up_axis = "xyz"[static_cast<int>(index.up_axis)];

  impl->cells.resize(index.cells.size());
  impl->cell_by_key.reserve(index.cells.size());
  for (size_t c = 0; c < index.cells.size(); ++c) {
    CellEntry& entry = impl->cells[c];
    entry.index = index.cells[c].index;
    entry.position = index.cells[c].position;
    entry.cameras = index.cells[c].cameras;
    for (int f = 0; f < kFaceCount; ++f) {
      const FrameRecord& frame = index.frames[c * kFaceCount + f];
      FaceEntry& face = entry.faces[f];
      face.type = frame.kind == FrameKind::kIntra ? FaceType::kIntra : FaceType::kPredicted;
      face.offset = frame.chunk_offset;
      face.coded_bytes = frame.payload_size;
      for (uint32_t ref : frame.references) {
        face.references.emplace_back(index.frames[ref].cell, index.frames[ref].face);
      }
    }
    impl->cell_by_key.emplace(cell_key(entry.index), c);
  }
  return std::unique_ptr<Reader>(new Reader(std::move(impl)));
}

const FileInfo& Reader::info() const { return impl_->info; }
const std::vector<CellEntry>& Reader::cells() const { return impl_->cells; }

std::optional<size_t> Reader::find_cell(const CellIndex& index) const {
  const auto it = impl_->cell_by_key.find(cell_key(index));
  if (it == impl_->cell_by_key.end()) return std::nullopt;
  return it->second;
}

std::optional<size_t> Reader::find_cell_at(const std::array<double, 3>& p) const {
  const GridSpec& grid = impl_->index.grid;
  int32_t idx[3];
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(p[axis])) return std::nullopt;
    // Cell i covers centre +- spacing/2 along each axis.
    const double t = std::floor((p[axis] - grid.origin[axis]) / grid.spacing[axis] + 0.5);
    if (t < 0 || t >= grid.dims[axis]) return std::nullopt;
    idx[axis] = static_cast<int32_t>(t);
  }
  return find_cell(CellIndex{idx[0], idx[1], idx[2]});
}

Result<ImageYCbCr420> Reader::decode_face_ycbcr(const CellIndex& cell, Face face) {
  SVC_ASSIGN_OR_RETURN(uint32_t frame, impl_->frame_of(cell, face));
  return impl_->decode_frame(frame);
}

Result<ImageRGB8> Reader::decode_face(const CellIndex& cell, Face face) {
  SVC_ASSIGN_OR_RETURN(ImageYCbCr420 ycc, decode_face_ycbcr(cell, face));
  ImageRGB8 rgb;
  rgb.width = ycc.width;
  rgb.height = ycc.height;
  rgb.pixels.resize(static_cast<size_t>(rgb.width) * rgb.height * 3);
  codec::ycbcr420_to_rgb(ycc, rgb.pixels.data());
  return rgb;
}

Result<std::array<ImageRGB8, kFaceCount>> Reader::decode_cube(const CellIndex& cell) {
  std::array<ImageRGB8, kFaceCount> cube;
  for (Face face : kAllFaces) {
    SVC_ASSIGN_OR_RETURN(cube[static_cast<int>(face)], decode_face(cell, face));
  }
  return cube;
}

Status Reader::verify() {
  std::string problems;
  int count = 0;
  for (int slot = 0; slot < 2; ++slot) {
    if (impl_->slot_damaged[slot]) {
      problems += (count ? "\n" : "") + impl_->file->path().string() + ": commit slot " + std::to_string(slot) +
                  " (bytes " + std::to_string(kFileHeaderSize + slot * kCommitSlotSize) + "-" +
                  std::to_string(kFileHeaderSize + (slot + 1) * kCommitSlotSize - 1) +
                  ") fails its CRC-32 check; the other slot's index is in use";
      ++count;
    }
  }
  for (uint32_t frame = 0; frame < impl_->index.frames.size(); ++frame) {
    auto payload = impl_->read_payload(frame);
    Status status = payload.status();
    if (status.ok()) {
      auto image = impl_->decode_frame(frame);
      status = image.status();
    }
    if (!status.ok()) {
      if (count < 20) problems += (count ? "\n" : "") + status.message();
      ++count;
    }
  }
  if (count == 0) return Status::Ok();
  if (count > 20) problems += "\n... and " + std::to_string(count - 20) + " more damaged faces";
  return Status(ErrorCode::kCorruptData, problems);
}

}  // namespace svc
