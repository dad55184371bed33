// SPDX-License-Identifier: BSD-2-Clause
#include "conformance/value_report.h"

#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/cfl.h"
#include "codec/common/cube_padding.h"
#include "codec/common/intra_frame.h"
#include "codec/common/intra_macroblock.h"
#include "codec/common/intra_prediction.h"
#include "codec/common/transform_size.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "common/file_io.h"
#include "container/container.h"
#include "svc/reader.h"

namespace svc::conformance {
namespace {

// The values the syntax allows, for the elements that have a fixed set.
const std::map<std::string, std::pair<int, int>>& allowed() {
  static const std::map<std::string, std::pair<int, int>> ranges = {
      {"I luma mode", {0, codec::kIntraModes - 1}},
      {"I chroma mode", {0, codec::kIntraModes - 1}},
      {"I CfL alpha (1/8)", {-codec::kCflMaxAlpha, codec::kCflMaxAlpha}},
      {"I luma transform size", {0, codec::kTransformSizes - 1}},
      {"I loop filter flags", {0, 3}},
      {"B filter bank", {0, 2}},
      {"B references", {1, 2}},
      {"B cube border units", {0, codec::kMaxCubeBorderUnits}},
      {"B warp mask", {0, 3}},
      {"B loop filter flags", {0, 3}},
      {"B macroblock coding", {0, 4}},
      {"B macroblock partition", {0, 3}},
      {"B macroblock warped", {0, 1}},
  };
  return ranges;
}

void tally_intra(const codec::CoefficientFrame& frame, ValueTally& tally) {
  tally["I qindex"].insert(frame.qindex);
  tally["I loop filter flags"].insert(frame.loop_filters);
  tally["I weighted matrix"].insert(frame.residual_matrix == codec::ResidualMatrix::kWeighted);
  for (codec::intra::LumaPartition partition : frame.luma_partitions) {
    codec::intra::for_each_luma_block(partition, [&](int, int, codec::TransformSize size) {
      tally["I luma transform size"].insert(static_cast<int>(size));
    });
  }
  const codec::BlockLayout layout = codec::block_layout(frame.width, frame.height);
  const size_t chroma = static_cast<size_t>(layout.chroma_blocks_x) * layout.chroma_blocks_y;
  const size_t luma = frame.block_modes.size() - 2 * chroma;
  for (size_t b = 0; b < frame.block_modes.size(); ++b) {
    const int mode = frame.block_modes[b];
    if (b < luma) {
      tally["I luma mode"].insert(mode);
    } else if (codec::is_cfl_mode_byte(mode)) {
      tally["I CfL alpha (1/8)"].insert(codec::cfl_alpha_of_mode_byte(mode));
    } else {
      tally["I chroma mode"].insert(mode);
    }
  }
}

void tally_bidirectional(const codec::BFrameHeader& header, ValueTally& tally) {
  tally["B qindex"].insert(header.qindex);
  tally["B filter bank"].insert(static_cast<int>(header.filter));
  tally["B references"].insert(header.reference_count);
  tally["B cube border units"].insert(header.border_units);
  tally["B warp mask"].insert(header.warp_mask);
  tally["B loop filter flags"].insert(header.loop_filters);
  tally["B epipolar lines"].insert(header.epipolar_lines);
  tally["B intra transform types"].insert(header.transform_types);
  tally["B inter transform sizes"].insert(header.inter_transform_sizes);
}

Status tally_payloads(const std::filesystem::path& stream, ValueTally& tally) {
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<ReadOnlyFile> file, ReadOnlyFile::open(stream));
  SVC_ASSIGN_OR_RETURN(OpenedContainer opened, open_container(*file, ReaderLimits{}));
  const ContainerIndex& index = opened.index;
  tally["index depth feature"].insert(index.depth);
  for (const FrameRecord& record : index.frames) {
    SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, read_frame_payload(*file, record, stream.string()));
    if (record.type == FaceType::kIntra) {
      codec::CoefficientFrame frame;
      SVC_RETURN_IF_ERROR(codec::parse_intra_frame(payload, static_cast<int>(index.face_width),
                                                   static_cast<int>(index.face_height), &frame));
      tally_intra(frame, tally);
    } else {
      codec::BFrameHeader header;
      SVC_RETURN_IF_ERROR(codec::parse_b_frame_header(payload, &header));
      tally_bidirectional(header, tally);
    }
  }
  return Status();
}

Status tally_macroblocks(const std::filesystem::path& stream, ValueTally& tally) {
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(stream));
  for (const CellEntry& cell : reader->cells()) {
    for (Face face : kAllFaces) {
      if (cell.faces[static_cast<int>(face)].type == FaceType::kIntra) continue;
      SVC_ASSIGN_OR_RETURN(InspectedFace inspected, reader->inspect_face(cell.index, face));
      for (size_t i = 0; i < inspected.modes.size(); ++i) {
        tally["B macroblock coding"].insert(static_cast<int>(inspected.modes[i]));
        tally["B macroblock partition"].insert(static_cast<int>(inspected.partitions[i]));
        tally["B macroblock warped"].insert(inspected.warped[i]);
      }
    }
  }
  return Status();
}

// "0..3, 7, 9..12"
std::string runs(const std::set<int>& values) {
  std::string text;
  for (auto it = values.begin(); it != values.end();) {
    int last = *it;
    auto next = std::next(it);
    while (next != values.end() && *next == last + 1) last = *next++;
    text += (text.empty() ? "" : ", ") + std::to_string(*it) + (last != *it ? ".." + std::to_string(last) : "");
    it = next;
  }
  return text;
}

}  // namespace

Status tally_values(const std::filesystem::path& stream, ValueTally* tally) {
  SVC_RETURN_IF_ERROR(tally_payloads(stream, *tally));
  return tally_macroblocks(stream, *tally);
}

void print_values(const ValueTally& tally) {
  for (const auto& [element, values] : tally) {
    std::string missing;
    if (auto range = allowed().find(element); range != allowed().end()) {
      std::set<int> absent;
      for (int v = range->second.first; v <= range->second.second; ++v) {
        if (!values.count(v)) absent.insert(v);
      }
      missing = absent.empty() ? "; every allowed value" : "; never: " + runs(absent);
    }
    std::printf("%-40s %zu values: %s%s\n", element.c_str(), values.size(), runs(values).c_str(), missing.c_str());
  }
}

}  // namespace svc::conformance
