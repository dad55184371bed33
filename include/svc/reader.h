// Random access to an .svc file by cell: what a walkthrough runtime embeds.
//
// Errors: no call throws; failures come back as Status / Result with a message naming
// the file, cell, face and byte offset at fault. A damaged face yields an error for
// that face (and the B-faces that reference it) while every other face stays readable.
//
// Threading: after open() returns, every const and non-const method of Reader may be
// called from any number of threads at once. Results are bit-identical to a
// single-threaded sequential decode, whatever the thread count or call order.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "svc/limits.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

struct ReaderSettings {
  // Caps on what the file may make the reader allocate (see svc/limits.h).
  ReaderLimits limits;
};

// Fills settings with the defaults documented on each field.
ReaderSettings default_reader_settings();

enum class FaceType : uint8_t { kIntra = 0, kPredicted = 1 };

struct FaceEntry {
  FaceType type = FaceType::kIntra;
  uint64_t offset = 0;      // file offset of the face's chunk
  uint64_t coded_bytes = 0; // coded payload size
  // Faces this one is predicted from: (cell ordinal, face). Empty for an I-face.
  std::vector<std::pair<uint32_t, Face>> references;
};

struct CellEntry {
  CellIndex index;
  std::array<double, 3> position{0, 0, 0};      // camera centre
  std::array<Camera, kFaceCount> cameras;       // indexed by Face
  std::array<FaceEntry, kFaceCount> faces;      // indexed by Face
};

struct FileInfo {
  uint16_t format_major = 0;
  uint16_t format_minor = 0;
  uint64_t file_bytes = 0;
  int face_width = 0;
  int face_height = 0;
  std::array<int32_t, 3> grid_dims{0, 0, 0};
  std::array<double, 3> grid_origin{0, 0, 0};
  std::array<double, 3> grid_spacing{1, 1, 1};
  int quality = 0;       // 0 when the file was encoded with an explicit quantiser scale
  int quant_scale = 0;
  std::array<int32_t, 3> i_spacing{1, 1, 1};
  std::string motion;    // "depth" or "logarithmic"
  char up_axis = 'y';
};

class Reader {
 public:
  // Opens `path` and reads its header and index (not the face data). The returned
  // reader owns the file handle until destroyed.
  static Result<std::unique_ptr<Reader>> open(const std::filesystem::path& path,
                                              const ReaderSettings& settings = default_reader_settings());
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const FileInfo& info() const;
  // All cells present in the file, sorted by (y, z, x). The reference stays valid for
  // the reader's lifetime.
  const std::vector<CellEntry>& cells() const;
  // Ordinal into cells() of the cell at a grid index, if present.
  std::optional<size_t> find_cell(const CellIndex& index) const;
  // Ordinal of the present cell whose grid cell contains world point `p`, if any.
  std::optional<size_t> find_cell_at(const std::array<double, 3>& p) const;

  // Decodes one face as RGB8 (tightly packed, row 0 at the top) or as YCbCr 4:2:0
  // planes. Reads only that face's bytes and those of its references.
  Result<ImageRGB8> decode_face(const CellIndex& cell, Face face);
  Result<ImageYCbCr420> decode_face_ycbcr(const CellIndex& cell, Face face);
  // The six faces of a cell, indexed by Face.
  Result<std::array<ImageRGB8, kFaceCount>> decode_cube(const CellIndex& cell);

  // Checks the CRC of every chunk and decodes every face. Returns the first problem
  // found, naming the damaged chunk (offset, cell, face); ok when the file is intact.
  Status verify();

  struct Impl;

 private:
  explicit Reader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace svc
