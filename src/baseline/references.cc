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
  int last_reference = -1;             // display index, decode order
  int reference_before_keyframe = -1;  // the latest reference decoded before that keyframe
  int keyframe_display = -1;
  for (FrameRecord& record : sequence->frames) {
    record.references.clear();
    if (record.keyframe) {
      reference_before_keyframe = last_reference;
      keyframe_display = record.display_index;
      last_reference = record.display_index;
      continue;
    }
    if (last_reference >= 0) record.references.push_back(last_reference);
    const bool leading = record.display_index < keyframe_display;
    if (leading && reference_before_keyframe >= 0) record.references.push_back(reference_before_keyframe);
    const uint8_t* data = sequence->stream.data() + record.offset;
    if (record.offset + record.size <= sequence->stream.size() &&
        is_reference_picture(sequence->decoder, data, record.size)) {
      last_reference = record.display_index;
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
