// svc inspect: a decoded face beside its macroblock classification (intra red,
// predicted green, skipped blue), as in the dissertation's Figure 4.5.
#include <cstdio>
#include <map>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "codec/bframe_codec.h"
#include "codec/color.h"
#include "codec/frame_codec.h"
#include "codec/motion.h"
#include "common/file_io.h"
#include "container/container.h"

namespace svc::cli {

namespace {

struct DecodedWithModes {
  ImageYCbCr420 image;
  std::vector<codec::MacroblockMode> modes;  // empty for an I-face: every macroblock intra
};

Result<ImageYCbCr420> decode_intra(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame) {
  const std::string what = "reference frame " + std::to_string(frame);
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, read_frame_payload(file, index.frames[frame], what));
  ImageYCbCr420 image;
  SVC_RETURN_IF_ERROR(codec::decode_intra_frame(payload, static_cast<int>(index.face_width),
                                                static_cast<int>(index.face_height), &image));
  return image;
}

Result<DecodedWithModes> decode_with_modes(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame) {
  const FrameRecord& record = index.frames[frame];
  DecodedWithModes out;
  if (record.kind == FrameKind::kIntra) {
    SVC_ASSIGN_OR_RETURN(out.image, decode_intra(file, index, frame));
    return out;
  }
  std::array<ImageYCbCr420, 2> refs;
  for (size_t r = 0; r < record.references.size(); ++r) {
    SVC_ASSIGN_OR_RETURN(refs[r], decode_intra(file, index, record.references[r]));
  }
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, read_frame_payload(file, record, "face"));
  SVC_RETURN_IF_ERROR(codec::decode_b_frame(payload, static_cast<int>(index.face_width),
                                            static_cast<int>(index.face_height), refs[0],
                                            record.references.size() > 1 ? &refs[1] : nullptr, &out.image,
                                            &out.modes));
  return out;
}

const char* mode_name(codec::MacroblockMode mode) {
  switch (mode) {
    case codec::MacroblockMode::kIntra: return "intra";
    case codec::MacroblockMode::kForward: return "forward";
    case codec::MacroblockMode::kBackward: return "backward";
    case codec::MacroblockMode::kBidirectional: return "bidirectional";
    case codec::MacroblockMode::kSkipped: return "skipped";
  }
  return "other";
}

// Intra red, any prediction green, skipped blue.
std::array<int, 3> mode_colour(codec::MacroblockMode mode) {
  switch (mode) {
    case codec::MacroblockMode::kIntra: return {230, 40, 40};
    case codec::MacroblockMode::kSkipped: return {40, 90, 240};
    default: return {40, 200, 60};
  }
}

}  // namespace

int inspect_command(const InspectOptions& options) {
  auto file = ReadOnlyFile::open(options.input);
  if (!file.ok()) return report_error(file.status());
  auto opened = open_container(**file, ReaderLimits{});
  if (!opened.ok()) return report_error(opened.status());
  const ContainerIndex& index = opened->index;
  int cell_ordinal = -1;
  for (size_t c = 0; c < index.cells.size(); ++c) {
    if (index.cells[c].index == options.cell) cell_ordinal = static_cast<int>(c);
  }
  if (cell_ordinal < 0) {
    return report_error(Status(ErrorCode::kNotFound, options.input.string() + " has no cell (" +
                                                         cell_text(options.cell) + ")"));
  }
  const uint32_t frame = static_cast<uint32_t>(cell_ordinal * kFaceCount + static_cast<int>(options.face));
  auto decoded = decode_with_modes(**file, index, frame);
  if (!decoded.ok()) {
    return report_error(decoded.status().with_context("cell (" + cell_text(options.cell) + ") face " +
                                                      face_name(options.face)));
  }
  const int w = static_cast<int>(index.face_width), h = static_cast<int>(index.face_height);
  const int mbw = (w + codec::kMacroblockSize - 1) / codec::kMacroblockSize;
  const int mbh = (h + codec::kMacroblockSize - 1) / codec::kMacroblockSize;
  std::vector<codec::MacroblockMode> modes = decoded->modes;
  if (modes.empty()) modes.assign(static_cast<size_t>(mbw) * mbh, codec::MacroblockMode::kIntra);

  std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3);
  codec::ycbcr420_to_rgb(decoded->image, rgb.data());
  // Left: the decoded face. Right: the same face, dimmed, tinted by macroblock mode,
  // with the macroblock grid drawn.
  const int gap = 8;
  ImageRGB8 sheet;
  sheet.width = 2 * w + gap;
  sheet.height = h;
  sheet.pixels.assign(static_cast<size_t>(sheet.width) * h * 3, 255);
  std::map<int, uint64_t> counts;
  for (codec::MacroblockMode m : modes) counts[static_cast<int>(m)] += 1;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint8_t* src = &rgb[(static_cast<size_t>(y) * w + x) * 3];
      uint8_t* left = &sheet.pixels[(static_cast<size_t>(y) * sheet.width + x) * 3];
      uint8_t* right = &sheet.pixels[(static_cast<size_t>(y) * sheet.width + w + gap + x) * 3];
      const auto colour = mode_colour(modes[static_cast<size_t>(y / 16) * mbw + x / 16]);
      const bool edge = x % 16 == 0 || y % 16 == 0;
      for (int c = 0; c < 3; ++c) {
        left[c] = src[c];
        right[c] = edge ? static_cast<uint8_t>(colour[c])
                        : static_cast<uint8_t>((src[c] * 2 + colour[c] * 3) / 5);
      }
    }
  }
  Status status = write_png(options.output, sheet);
  if (!status.ok()) return report_error(status);
  std::printf("cell (%s) face %s: %s-face, %d macroblocks:", cell_text(options.cell).c_str(), face_name(options.face),
              index.frames[frame].kind == FrameKind::kIntra ? "I" : "B", mbw * mbh);
  for (const auto& [mode, count] : counts) {
    std::printf(" %s %llu", mode_name(static_cast<codec::MacroblockMode>(mode)),
                static_cast<unsigned long long>(count));
  }
  std::printf("\nwrote %s (left: decoded face; right: intra red, predicted green, skipped blue)\n",
              options.output.string().c_str());
  return 0;
}

}  // namespace svc::cli
