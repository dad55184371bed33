// SPDX-License-Identifier: BSD-2-Clause
// Loading one face of an svc-input database: color to 8-bit RGB, depth to eye z.
#include "database/database.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "database/png_chunks.h"

namespace svc {

namespace {

namespace fs = std::filesystem;

std::string in_quotes(const std::string& text) { return "\"" + text + "\""; }

// ---------------------------------------------------------------------------------------
// Faces

// The image library's first line: the rest repeats it in other words.
std::string first_line(const std::string& message) { return message.substr(0, message.find('\n')); }

// All channels of an image: as stored when every channel is 8-bit (most color files),
// else as float (integer types normalised to [0,1] by OpenImageIO).
struct DecodedImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::string> channel_names;
  std::vector<OIIO::TypeDesc> channel_types;
  std::vector<float> pixels;   // width * height * channels, interleaved; empty when eight_bit()
  std::vector<uint8_t> bytes;  // the same when every channel is UINT8, else empty
  bool eight_bit() const { return !bytes.empty(); }
};

// `what` is the prefix naming cell, face, role and file.
Result<DecodedImage> read_face_image(const fs::path& resolved, const std::string& what, int expected_width,
                                     int expected_height) {
  std::error_code ec;
  const fs::file_status status = fs::status(resolved, ec);
  if (!fs::exists(status)) return Status(ErrorCode::kNotFound, what + ": file not found");
  if (!fs::is_regular_file(status)) {
    return Status(ErrorCode::kNotFound, what + ": not a regular file");
  }
  {
    std::ifstream probe(resolved, std::ios::binary);
    if (!probe) return Status(ErrorCode::kIoError, what + ": cannot open the file for reading");
  }
  SVC_RETURN_IF_ERROR(check_png_chunks(resolved, what));
  // Color values are taken as stored: without this OpenImageIO premultiplies the color
  // of PNG and TIFF files with unassociated alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(resolved.string(), &config);
  if (!input) {
    return Status(ErrorCode::kBadInput, what + ": not a readable image: " + first_line(OIIO::geterror()));
  }
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.width != expected_width || spec.height != expected_height || spec.depth != 1) {
    return Status(ErrorCode::kBadInput, what + ": image is " + std::to_string(spec.width) + "x" +
                                            std::to_string(spec.height) + (spec.depth != 1 ? " (a volume)" : "") +
                                            ", face_size is " + std::to_string(expected_width) + "x" +
                                            std::to_string(expected_height));
  }
  if (spec.nchannels <= 0 || spec.nchannels > kMaxImageChannels) {
    return Status(ErrorCode::kBadInput, what + ": image has " + std::to_string(spec.nchannels) + " channels");
  }
  DecodedImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  for (int c = 0; c < spec.nchannels; ++c) {
    image.channel_names.push_back(c < static_cast<int>(spec.channelnames.size()) ? spec.channelnames[c]
                                                                                 : std::string());
    image.channel_types.push_back(spec.channelformat(c));
  }
  const size_t values = static_cast<size_t>(spec.width) * spec.height * spec.nchannels;
  // Reading 8-bit files as bytes skips a float copy four times their size; to_rgb8 gets
  // the same values either way.
  const bool eight_bit = std::all_of(image.channel_types.begin(), image.channel_types.end(),
                                     [](const OIIO::TypeDesc& type) { return type == OIIO::TypeDesc::UINT8; });
  bool read = false;
  if (eight_bit) {
    image.bytes.resize(values);
    read = input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, image.bytes.data());
  } else {
    image.pixels.resize(values);
    read = input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data());
  }
  if (!read) {
    return Status(ErrorCode::kBadInput, what + ": cannot decode the image: " + first_line(input->geterror()));
  }
  return image;
}

bool is_float_type(const OIIO::TypeDesc& type) {
  return type.basetype == OIIO::TypeDesc::HALF || type.basetype == OIIO::TypeDesc::FLOAT ||
         type.basetype == OIIO::TypeDesc::DOUBLE;
}

int find_channel(const DecodedImage& image, const std::string& name) {
  for (int c = 0; c < image.channels; ++c) {
    if (image.channel_names[c] == name) return c;
  }
  return -1;
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// R, G, B by name, else "<layer>.R/G/B" of the first layer that has all three, else the
// first three channels, else grey (channel 0) for one- and two-channel images.
std::array<int, 3> color_channels(const DecodedImage& image) {
  const int r = find_channel(image, "R"), g = find_channel(image, "G"), b = find_channel(image, "B");
  if (r >= 0 && g >= 0 && b >= 0) return {r, g, b};
  for (int c = 0; c < image.channels; ++c) {
    const std::string& name = image.channel_names[c];
    if (!ends_with(name, ".R")) continue;
    const std::string layer = name.substr(0, name.size() - 1);
    const int lg = find_channel(image, layer + "G"), lb = find_channel(image, layer + "B");
    if (lg >= 0 && lb >= 0) return {c, lg, lb};
  }
  if (image.channels >= 3) return {0, 1, 2};
  return {0, 0, 0};
}

// Z, any *.Z, depth, Y, else the only channel; -1 when none fits.
int depth_channel(const DecodedImage& image) {
  if (const int c = find_channel(image, "Z"); c >= 0) return c;
  for (int c = 0; c < image.channels; ++c) {
    if (ends_with(image.channel_names[c], ".Z")) return c;
  }
  if (const int c = find_channel(image, "depth"); c >= 0) return c;
  if (const int c = find_channel(image, "Y"); c >= 0) return c;
  if (image.channels == 1) return 0;
  return -1;
}

std::string channel_list(const DecodedImage& image) {
  std::string list;
  for (int c = 0; c < image.channels; ++c) {
    if (c) list += ", ";
    list += image.channel_names[c].empty() ? "(unnamed)" : image.channel_names[c];
  }
  return list;
}

ImageRGB8 to_rgb8(const DecodedImage& image) {
  const std::array<int, 3> channels = color_channels(image);
  const bool linear = is_float_type(image.channel_types[channels[0]]);
  ImageRGB8 out;
  out.width = image.width;
  out.height = image.height;
  const size_t pixel_count = static_cast<size_t>(image.width) * image.height;
  out.pixels.resize(pixel_count * 3);
  if (image.eight_bit()) {
    for (size_t i = 0; i < pixel_count; ++i) {
      const uint8_t* px = &image.bytes[i * image.channels];
      for (int k = 0; k < 3; ++k) out.pixels[i * 3 + k] = px[channels[k]];
    }
    return out;
  }
  for (size_t i = 0; i < pixel_count; ++i) {
    const float* px = &image.pixels[i * image.channels];
    for (int k = 0; k < 3; ++k) {
      const float v = px[channels[k]];
      uint8_t coded;
      if (linear) {
        coded = linear_to_srgb8(v);
      } else {
        // Integer images arrive normalised to [0,1]; 8-bit values come back exactly and
        // wider ones are rounded to the nearest 8-bit value.
        // (v is non-negative after the clamp, so adding one half and truncating rounds.)
        coded = static_cast<uint8_t>(static_cast<double>(std::clamp(v, 0.0f, 1.0f)) * 255.0 + 0.5);
      }
      out.pixels[i * 3 + k] = coded;
    }
  }
  return out;
}

std::vector<float> to_eye_depth(const DecodedImage& image, int channel, DepthMode mode, const Frustum& frustum) {
  const int w = image.width, h = image.height;
  std::vector<float> depth(static_cast<size_t>(w) * h);
  constexpr float kBackground = std::numeric_limits<float>::infinity();
  // For radial depth, eye z = radial * near / |(x_cam, y_cam, -near)| at the pixel centre.
  std::vector<double> x_cam, y_cam;
  if (mode == DepthMode::kRadial) {
    x_cam.resize(w);
    y_cam.resize(h);
    for (int i = 0; i < w; ++i) {
      const double ndc_x = (i + 0.5) / w * 2 - 1;
      x_cam[i] = 0.5 * (frustum.left + frustum.right) + ndc_x * 0.5 * (frustum.right - frustum.left);
    }
    for (int j = 0; j < h; ++j) {
      const double ndc_y = 1 - (j + 0.5) / h * 2;
      y_cam[j] = 0.5 * (frustum.bottom + frustum.top) + ndc_y * 0.5 * (frustum.top - frustum.bottom);
    }
  }
  const double n = frustum.near_plane;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const size_t p = static_cast<size_t>(j) * w + i;
      const float raw = image.pixels[p * image.channels + channel];
      if (!std::isfinite(raw) || raw <= 0) {
        depth[p] = kBackground;
        continue;
      }
      double eye_z = raw;
      if (mode == DepthMode::kRadial) {
        eye_z = raw * n / std::sqrt(x_cam[i] * x_cam[i] + y_cam[j] * y_cam[j] + n * n);
      }
      depth[p] = eye_z >= frustum.far_plane ? kBackground : static_cast<float>(eye_z);
    }
  }
  return depth;
}

}  // namespace

uint8_t linear_to_srgb8(float linear) noexcept {
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  const double v = linear;
  const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return static_cast<uint8_t>(std::lround(std::clamp(encoded, 0.0, 1.0) * 255.0));
}

void configure_image_loading() {
  // No OpenEXR thread pool (faces load on svc's own threads) and the core library, which
  // reads faster to the same bytes (docs/bench.md, "Figures behind code constants").
  OIIO::attribute("exr_threads", -1);
  OIIO::attribute("openexr:core", 1);
}

Result<FaceData> load_face(const DatabaseManifest& manifest, size_t cell_ordinal, Face face) {
  SVC_ASSIGN_OR_RETURN(const CellSource cell, read_cell(manifest, cell_ordinal));
  return load_face(manifest, cell, face);
}

namespace {

// Where a face's files are and how errors name them.
struct FaceFiles {
  const FaceSource* source = nullptr;
  fs::path color_path, depth_path;
  std::string color_what, depth_what;
};

Result<FaceFiles> face_files(const DatabaseManifest& manifest, const CellSource& cell, Face face) {
  const auto face_slot = static_cast<size_t>(face);
  if (face_slot >= kFaceCount) {
    return Status(ErrorCode::kInvalidArgument, "face " + std::to_string(face_slot) + " is out of range");
  }
  FaceFiles files;
  files.source = &cell.faces[face_slot];
  const std::string where = cell_label(cell.index) + ", face " + face_name(face);
  if (!lists_face(cell.listed_faces, face)) {
    return Status(ErrorCode::kInvalidArgument, where + ": the manifest does not list this face");
  }
  files.color_path = resolve_database_path(manifest, files.source->color_path);
  files.depth_path = resolve_database_path(manifest, files.source->depth_path);
  const auto describe = [&](const char* role, const std::string& path, const fs::path& resolved) {
    return where + ", " + role + " file " + in_quotes(path) + " (" + resolved.string() + ")";
  };
  files.color_what = describe("color", files.source->color_path, files.color_path);
  files.depth_what = describe("depth", files.source->depth_path, files.depth_path);
  return files;
}

// Eye-space depth from the face's depth image (read already).
Result<std::vector<float>> eye_depth(const DatabaseManifest& manifest, const FaceFiles& files,
                                     const DecodedImage& depth_image) {
  const int channel = depth_channel(depth_image);
  if (channel < 0) {
    return Status(ErrorCode::kBadInput, files.depth_what +
                                            ": no depth channel (looked for Z, *.Z, "
                                            "depth, Y; the image has " +
                                            channel_list(depth_image) + ")");
  }
  if (!is_float_type(depth_image.channel_types[channel])) {
    return Status(ErrorCode::kBadInput, files.depth_what + ": depth channel " +
                                            in_quotes(depth_image.channel_names[channel]) + " holds " +
                                            depth_image.channel_types[channel].c_str() +
                                            " values; depth must be half or float");
  }
  return to_eye_depth(depth_image, channel, manifest.depth_mode, files.source->camera.frustum);
}

}  // namespace

Result<FaceData> load_face(const DatabaseManifest& manifest, const CellSource& cell, Face face) {
  SVC_ASSIGN_OR_RETURN(const FaceFiles files, face_files(manifest, cell, face));
  SVC_ASSIGN_OR_RETURN(const DecodedImage color_image, read_face_image(files.color_path, files.color_what,
                                                                       manifest.face_width, manifest.face_height));
  // Color and depth often share one EXR; read it once then.
  const bool shared_file = files.depth_path == files.color_path;
  DecodedImage depth_storage;
  if (!shared_file) {
    SVC_ASSIGN_OR_RETURN(depth_storage, read_face_image(files.depth_path, files.depth_what, manifest.face_width,
                                                        manifest.face_height));
  }
  FaceData data;
  SVC_ASSIGN_OR_RETURN(data.depth, eye_depth(manifest, files, shared_file ? color_image : depth_storage));
  data.color = to_rgb8(color_image);
  return data;
}

Result<std::vector<float>> load_face_depth(const DatabaseManifest& manifest, const CellSource& cell, Face face) {
  SVC_ASSIGN_OR_RETURN(const FaceFiles files, face_files(manifest, cell, face));
  SVC_ASSIGN_OR_RETURN(const DecodedImage depth_image, read_face_image(files.depth_path, files.depth_what,
                                                                       manifest.face_width, manifest.face_height));
  return eye_depth(manifest, files, depth_image);
}

Result<ImageRGB8> load_face_color(const DatabaseManifest& manifest, size_t cell_ordinal, Face face) {
  SVC_ASSIGN_OR_RETURN(const CellSource cell, read_cell(manifest, cell_ordinal));
  SVC_ASSIGN_OR_RETURN(const FaceFiles files, face_files(manifest, cell, face));
  SVC_ASSIGN_OR_RETURN(const DecodedImage color_image, read_face_image(files.color_path, files.color_what,
                                                                       manifest.face_width, manifest.face_height));
  return to_rgb8(color_image);
}

}  // namespace svc
