// SPDX-License-Identifier: BSD-2-Clause
#include "baseline/references.h"

namespace svc::baseline::detail {

void link_mpeg2_references(EncodedSequence* sequence) {
  int last_anchor = -1, previous_anchor = -1;
  for (FrameRecord& record : sequence->frames) {
    record.references.clear();
    if (record.type == PictureType::kP && last_anchor >= 0) {
      record.references = {last_anchor};
    } else if (record.type == PictureType::kB) {
      if (previous_anchor >= 0) record.references.push_back(previous_anchor);
      if (last_anchor >= 0) record.references.push_back(last_anchor);
    }
    if (record.type != PictureType::kB) {
      previous_anchor = last_anchor;
      last_anchor = record.display_index;
    }
  }
}

void link_chained_references(EncodedSequence* sequence) {
  int last_trailing = -1;              // latest reference shown after the latest keyframe
  int last_leading = -1;               // latest reference shown before it (open GOP)
  int reference_before_keyframe = -1;  // latest trailing reference of the previous GOP
  int keyframe_display = -1;
  for (FrameRecord& record : sequence->frames) {
    record.references.clear();
    if (record.keyframe) {
      reference_before_keyframe = last_trailing;
      keyframe_display = last_trailing = record.display_index;
      last_leading = -1;
      continue;
    }
    const bool leading = record.display_index < keyframe_display;
    if (leading) {
      record.references.push_back(last_leading >= 0 ? last_leading : last_trailing);
      if (reference_before_keyframe >= 0) record.references.push_back(reference_before_keyframe);
    } else if (last_trailing >= 0) {
      record.references.push_back(last_trailing);
    }
    const uint8_t* data = sequence->stream.data() + record.offset;
    if (record.offset + record.size <= sequence->stream.size() &&
        is_reference_picture(sequence->decoder, data, record.size)) {
      (leading ? last_leading : last_trailing) = record.display_index;
    }
  }
}

bool is_reference_picture(const std::string& decoder, const uint8_t* data, size_t size) {
  const bool h264 = decoder == "h264", hevc = decoder == "hevc";
  if (!h264 && !hevc) return true;
  for (size_t i = 0; i + 3 < size; ++i) {
    if (data[i] != 0 || data[i + 1] != 0 || data[i + 2] != 1) continue;
    const uint8_t header = data[i + 3];
    if (h264) {
      const int type = header & 0x1f;
      if (type >= 1 && type <= 5) return (header >> 5) != 0;
    } else {
      const int type = (header >> 1) & 0x3f;
      if (type <= 31) return !(type <= 14 && type % 2 == 0);
    }
  }
  return true;
}

}  // namespace svc::baseline::detail
