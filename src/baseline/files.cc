// SPDX-License-Identifier: BSD-2-Clause
// Baseline files: elementary stream + JSON index per face sequence, a database directory,
// and PNG images through libavcodec.
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>

#include <nlohmann/json.hpp>

#include "baseline/baseline.h"
#include "baseline/ffmpeg_util.h"

namespace svc::baseline {

using detail::av_error;
using detail::CodecContextPtr;
using detail::FramePtr;
using detail::PacketPtr;
using json = nlohmann::json;

namespace {

// Caps on what an index may claim, checked before anything is allocated from it.
constexpr int kMaxSide = 16384;
constexpr int64_t kMaxFrames = int64_t{1} << 24;
constexpr uint64_t kMaxExtradataBytes = 1 << 20;

Result<std::vector<uint8_t>> read_bytes(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    return Status(ErrorCode::kNotFound, path.string() + " does not exist");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(ErrorCode::kIoError, "cannot open " + path.string());
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return Status(ErrorCode::kIoError, "cannot read " + path.string());
  return bytes;
}

Status write_bytes(const std::filesystem::path& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Status(ErrorCode::kIoError, "cannot create " + path.string());
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + path.string());
  return Status::Ok();
}

std::string to_hex(const std::vector<uint8_t>& bytes) {
  static const char digits[] = "0123456789abcdef";
  std::string text;
  text.reserve(bytes.size() * 2);
  for (uint8_t b : bytes) {
    text.push_back(digits[b >> 4]);
    text.push_back(digits[b & 15]);
  }
  return text;
}

bool from_hex(const std::string& text, std::vector<uint8_t>* bytes) {
  if (text.size() % 2 != 0) return false;
  auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  bytes->clear();
  for (size_t i = 0; i < text.size(); i += 2) {
    const int hi = nibble(text[i]), lo = nibble(text[i + 1]);
    if (hi < 0 || lo < 0) return false;
    bytes->push_back(static_cast<uint8_t>(hi * 16 + lo));
  }
  return true;
}

std::filesystem::path index_path(const std::filesystem::path& stream_path) {
  return std::filesystem::path(stream_path.string() + ".index.json");
}

Result<json> read_json(const std::filesystem::path& path) {
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, read_bytes(path));
  json document = json::parse(bytes.begin(), bytes.end(), nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded() || !document.is_object()) {
    return Status(ErrorCode::kCorruptData, path.string() + " is not a JSON object");
  }
  return document;
}

// Validates `sequence` as read from files: every claim is checked against the stream.
Status validate_sequence(const EncodedSequence& sequence) {
  const int count = sequence.frame_count();
  std::vector<int> positions(count, -1);
  for (int position = 0; position < count; ++position) {
    const FrameRecord& record = sequence.frames[position];
    const std::string where = "frame record " + std::to_string(position);
    if (record.display_index < 0 || record.display_index >= count || positions[record.display_index] != -1) {
      return Status(ErrorCode::kCorruptData, where + ": display index " + std::to_string(record.display_index) +
                                                 " is out of range or repeated");
    }
    if (record.offset > sequence.stream.size() || record.size > sequence.stream.size() - record.offset) {
      return Status(ErrorCode::kCorruptData, where + ": bytes " + std::to_string(record.offset) + "+" +
                                                 std::to_string(record.size) + " lie outside the stream of " +
                                                 std::to_string(sequence.stream.size()));
    }
    positions[record.display_index] = position;
  }
  for (int position = 0; position < count; ++position) {
    for (int reference : sequence.frames[position].references) {
      if (reference < 0 || reference >= count || positions[reference] >= position) {
        return Status(ErrorCode::kCorruptData, "frame record " + std::to_string(position) + ": reference " +
                                                   std::to_string(reference) +
                                                   " is not an earlier frame in decode order");
      }
    }
  }
  return Status::Ok();
}

Result<EncodedSequence> sequence_from_json(const json& index, std::vector<uint8_t> stream,
                                           const std::string& where) {
  EncodedSequence sequence;
  try {
    if (index.value("format", "") != "svc-baseline-index" || index.value("version", 0) != 1) {
      return Status(ErrorCode::kCorruptData, where + " is not an svc-baseline-index v1");
    }
    sequence.encoder = index.at("encoder").get<std::string>();
    sequence.decoder = index.at("decoder").get<std::string>();
    sequence.width = index.at("width").get<int>();
    sequence.height = index.at("height").get<int>();
    if (sequence.width < 1 || sequence.height < 1 || sequence.width > kMaxSide || sequence.height > kMaxSide) {
      return Status(ErrorCode::kCorruptData, where + ": frame size out of range");
    }
    const std::string extradata = index.value("extradata", "");
    if (extradata.size() > 2 * kMaxExtradataBytes || !from_hex(extradata, &sequence.extradata)) {
      return Status(ErrorCode::kCorruptData, where + ": bad extradata");
    }
    const json& frames = index.at("frames");
    if (!frames.is_array() || frames.empty() || static_cast<int64_t>(frames.size()) > kMaxFrames) {
      return Status(ErrorCode::kCorruptData, where + ": \"frames\" must be a non-empty array");
    }
    sequence.frames.reserve(frames.size());
    for (const json& entry : frames) {
      FrameRecord record;
      record.display_index = entry.at("display").get<int>();
      record.offset = entry.at("offset").get<uint64_t>();
      record.size = entry.at("size").get<uint32_t>();
      const std::string type = entry.at("type").get<std::string>();
      if (type == "I")
        record.type = PictureType::kI;
      else if (type == "P")
        record.type = PictureType::kP;
      else if (type == "B")
        record.type = PictureType::kB;
      else
        return Status(ErrorCode::kCorruptData, where + ": picture type '" + type + "'");
      record.keyframe = entry.at("key").get<bool>();
      const json& refs = entry.at("refs");
      if (!refs.is_array() || refs.size() > 16) {
        return Status(ErrorCode::kCorruptData, where + ": bad \"refs\"");
      }
      for (const json& ref : refs) record.references.push_back(ref.get<int>());
      sequence.frames.push_back(std::move(record));
    }
  } catch (const json::exception& e) {
    return Status(ErrorCode::kCorruptData, where + ": " + e.what());
  }
  sequence.stream = std::move(stream);
  Status valid = validate_sequence(sequence);
  if (!valid.ok()) return valid.with_context(where);
  sequence.decode_position.assign(sequence.frames.size(), -1);
  for (size_t position = 0; position < sequence.frames.size(); ++position) {
    sequence.decode_position[sequence.frames[position].display_index] = static_cast<int>(position);
  }
  return sequence;
}

}  // namespace

std::string stream_extension(const std::string& encoder) {
  if (encoder == "mpeg2video") return "m2v";
  if (encoder == "libx264") return "h264";
  if (encoder == "libx265") return "hevc";
  if (encoder == "libaom-av1" || encoder == "libsvtav1" || encoder == "librav1e") return "obu";
  if (encoder == "mjpeg") return "mjpeg";
  if (encoder == "png") return "pngs";
  if (encoder == "libwebp") return "webps";
  if (encoder == "libjxl") return "jxls";
  return "bin";
}

Status write_sequence(const EncodedSequence& sequence, const std::filesystem::path& stream_path) {
  json frames = json::array();
  for (const FrameRecord& record : sequence.frames) {
    frames.push_back({{"display", record.display_index},
                      {"offset", record.offset},
                      {"size", record.size},
                      {"type", std::string(1, picture_type_letter(record.type))},
                      {"key", record.keyframe},
                      {"refs", record.references}});
  }
  json index = {{"format", "svc-baseline-index"},
                {"version", 1},
                {"encoder", sequence.encoder},
                {"decoder", sequence.decoder},
                {"width", sequence.width},
                {"height", sequence.height},
                {"extradata", to_hex(sequence.extradata)},
                {"frames", std::move(frames)}};
  SVC_RETURN_IF_ERROR(write_bytes(stream_path, sequence.stream.data(), sequence.stream.size()));
  const std::string text = index.dump(1);
  return write_bytes(index_path(stream_path), text.data(), text.size());
}

Result<EncodedSequence> read_sequence(const std::filesystem::path& stream_path) {
  SVC_ASSIGN_OR_RETURN(json index, read_json(index_path(stream_path)));
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> stream, read_bytes(stream_path));
  return sequence_from_json(index, std::move(stream), index_path(stream_path).string());
}

Status write_database(const EncodedDatabase& database, const std::filesystem::path& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error) return Status(ErrorCode::kIoError, "cannot create " + directory.string());
  json cells = json::array();
  for (const CellIndex& c : database.layout.cells) cells.push_back({c.x, c.y, c.z});
  json faces = json::object();
  for (Face face : kAllFaces) {
    const EncodedSequence& sequence = database.faces[static_cast<int>(face)];
    const std::string name = std::string(face_name(face)) + "." + stream_extension(sequence.encoder);
    SVC_RETURN_IF_ERROR(write_sequence(sequence, directory / name));
    faces[face_name(face)] = name;
  }
  json manifest = {{"format", "svc-baseline"},
                   {"version", 1},
                   {"order", cell_order_name(database.layout.order)},
                   {"dims", database.layout.dims},
                   {"cells", std::move(cells)},
                   {"gop_start", database.layout.gop_start},
                   {"faces", std::move(faces)}};
  const std::string text = manifest.dump(1);
  return write_bytes(directory / "baseline.json", text.data(), text.size());
}

Result<EncodedDatabase> read_database(const std::filesystem::path& directory) {
  const std::filesystem::path manifest_path = directory / "baseline.json";
  SVC_ASSIGN_OR_RETURN(json manifest, read_json(manifest_path));
  const std::string where = manifest_path.string();
  EncodedDatabase database;
  std::array<std::string, kFaceCount> face_files;
  try {
    if (manifest.value("format", "") != "svc-baseline" || manifest.value("version", 0) != 1) {
      return Status(ErrorCode::kCorruptData, where + " is not an svc-baseline v1 manifest");
    }
    if (!parse_cell_order(manifest.at("order").get<std::string>(), &database.layout.order)) {
      return Status(ErrorCode::kCorruptData, where + ": unknown cell order");
    }
    database.layout.dims = manifest.at("dims").get<std::array<int, 3>>();
    const json& cells = manifest.at("cells");
    const json& gop_start = manifest.at("gop_start");
    if (!cells.is_array() || !gop_start.is_array() || cells.size() != gop_start.size() ||
        static_cast<int64_t>(cells.size()) > kMaxFrames) {
      return Status(ErrorCode::kCorruptData, where + ": \"cells\" and \"gop_start\" disagree");
    }
    for (size_t k = 0; k < cells.size(); ++k) {
      const auto c = cells[k].get<std::array<int, 3>>();
      database.layout.cells.push_back({c[0], c[1], c[2]});
      database.layout.gop_start.push_back(gop_start[k].get<int>() != 0 ? 1 : 0);
    }
    for (Face face : kAllFaces) {
      face_files[static_cast<int>(face)] = manifest.at("faces").at(face_name(face)).get<std::string>();
    }
  } catch (const json::exception& e) {
    return Status(ErrorCode::kCorruptData, where + ": " + e.what());
  }
  for (Face face : kAllFaces) {
    const std::string& file = face_files[static_cast<int>(face)];
    if (file.empty() || std::filesystem::path(file).has_parent_path()) {
      return Status(ErrorCode::kCorruptData, where + ": face " + face_name(face) + " file must be a plain name");
    }
    SVC_ASSIGN_OR_RETURN(database.faces[static_cast<int>(face)], read_sequence(directory / file));
    if (database.faces[static_cast<int>(face)].frames.size() != database.layout.cells.size()) {
      return Status(ErrorCode::kCorruptData,
                    where + ": face " + face_name(face) + " has " +
                        std::to_string(database.faces[static_cast<int>(face)].frames.size()) + " frames for " +
                        std::to_string(database.layout.cells.size()) + " cells");
    }
  }
  return database;
}

Status write_png(const ImageRGB8& image, const std::filesystem::path& path) {
  const AVCodec* encoder = avcodec_find_encoder(AV_CODEC_ID_PNG);
  if (!encoder) return Status(ErrorCode::kUnsupported, "this libavcodec has no PNG encoder");
  SVC_ASSIGN_OR_RETURN(FramePtr frame, detail::rgb_to_frame(image, AV_PIX_FMT_RGB24, false));
  CodecContextPtr context(avcodec_alloc_context3(encoder));
  if (!context) return Status(ErrorCode::kInternal, "out of memory allocating an encoder");
  context->width = image.width;
  context->height = image.height;
  context->pix_fmt = AV_PIX_FMT_RGB24;
  context->time_base = AVRational{1, 25};
  context->thread_count = 1;
  if (int err = avcodec_open2(context.get(), encoder, nullptr); err < 0) {
    return av_error("opening the PNG encoder", err);
  }
  frame->pts = 0;
  if (int err = avcodec_send_frame(context.get(), frame.get()); err < 0) {
    return av_error("encoding PNG " + path.string(), err);
  }
  avcodec_send_frame(context.get(), nullptr);
  PacketPtr packet(av_packet_alloc());
  if (!packet) return Status(ErrorCode::kInternal, "out of memory allocating a packet");
  if (int err = avcodec_receive_packet(context.get(), packet.get()); err < 0) {
    return av_error("encoding PNG " + path.string(), err);
  }
  return write_bytes(path, packet->data, static_cast<size_t>(packet->size));
}

Result<ImageRGB8> read_png(const std::filesystem::path& path) {
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, read_bytes(path));
  SVC_ASSIGN_OR_RETURN(CodecContextPtr context, detail::open_decoder("png", nullptr, 0));
  PacketPtr packet(av_packet_alloc());
  FramePtr frame(av_frame_alloc());
  if (!packet || !frame) return Status(ErrorCode::kInternal, "out of memory (PNG decoder)");
  if (int err = av_new_packet(packet.get(), static_cast<int>(bytes.size())); err < 0) {
    return av_error("allocating a packet", err);
  }
  std::memcpy(packet->data, bytes.data(), bytes.size());
  packet->flags |= AV_PKT_FLAG_KEY;
  int err = avcodec_send_packet(context.get(), packet.get());
  if (err >= 0) err = avcodec_send_packet(context.get(), nullptr);
  if (err >= 0 || err == AVERROR_EOF) err = avcodec_receive_frame(context.get(), frame.get());
  if (err < 0) {
    Status status = av_error("decoding " + path.string(), err);
    return Status(ErrorCode::kBadInput, status.message());
  }
  return detail::frame_to_rgb(*frame);
}

}  // namespace svc::baseline
