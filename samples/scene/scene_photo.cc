// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene_photo.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <system_error>

#include <OpenImageIO/imageio.h>

namespace svc::samples::detail {

namespace fs = std::filesystem;

const std::vector<std::string> kTextureSkipWords = {"_lm",    "light", "glow",   "blend", "fx",    "_ow",   "spec",
                                                    "norm",   "bump",  "mask",   "alpha", "trim",  "flare", "fog",
                                                    "liquid", "decal", "button", "lava",  "water", "slime"};

namespace {

constexpr std::array<const char*, 7> kImageExtensions = {".jpg", ".jpeg", ".tga", ".png", ".bmp", ".tif", ".tiff"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool contains_any(const std::string& text, const std::vector<std::string>& words) {
  return std::any_of(words.begin(), words.end(),
                     [&](const std::string& w) { return text.find(w) != std::string::npos; });
}

// Normal, specular, gloss and height maps that ship beside a colour image, named by a
// suffix: "wall01_nm.png" is a map of "wall01.png", not a colour image.
bool is_surface_map(const std::string& name) {
  const std::string stem = lower(fs::path(name).stem().string());
  for (const char* suffix : {"_nm", "_sm", "_gm", "_hm"}) {
    if (stem.size() > 3 && stem.compare(stem.size() - 3, 3, suffix) == 0) return true;
  }
  return false;
}

// FNV-1a over the name, mixed with the seed: an order that does not follow the folder
// layout, so that consecutive materials do not take near-identical variants.
uint64_t name_hash(const std::string& name, uint32_t seed) {
  uint64_t h = 0xCBF29CE484222325ull ^ (seed * 0x9E3779B97F4A7C15ull);
  for (unsigned char c : name) h = (h ^ c) * 0x100000001B3ull;
  h ^= h >> 29;
  return h * 0xBF58476D1CE4E5B9ull;
}

TextureClass class_of(Pattern pattern) {
  switch (pattern) {
    case Pattern::kTiles: return TextureClass::kTile;
    case Pattern::kBricks: return TextureClass::kBrick;
    case Pattern::kPlanks: return TextureClass::kWood;
    case Pattern::kConcrete: return TextureClass::kConcrete;
    case Pattern::kPlaster:
    case Pattern::kStripes: return TextureClass::kWall;
    case Pattern::kMetal: return TextureClass::kMetal;
    case Pattern::kGround: return TextureClass::kGrass;
    case Pattern::kPanels: return TextureClass::kCeiling;
    case Pattern::kPaving: return TextureClass::kPaving;
    case Pattern::kFabric: return TextureClass::kFabric;
    case Pattern::kLeaves: return TextureClass::kLeaves;
    case Pattern::kGlass: return TextureClass::kWindow;
  }
  return TextureClass::kWall;
}

// Metres one repeat of the image covers: game textures show a few bricks, planks or
// tiles across, about what a metre or two of the real surface holds.
double repeat_metres(TextureClass c) {
  switch (c) {
    case TextureClass::kBrick: return 1.5;
    case TextureClass::kWood: return 1.2;
    case TextureClass::kMetal: return 1.5;
    case TextureClass::kTile: return 1.5;
    case TextureClass::kGrass: return 4.0;
    case TextureClass::kPaving: return 2.5;
    case TextureClass::kFabric: return 0.8;
    case TextureClass::kLeaves: return 1.5;
    default: return 2.0;
  }
}

double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

float srgb_to_linear(int code) {
  const double s = code / 255.0;
  return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

// True when more than 1 % of the pixels are mostly transparent: a cut-out (grate, fence,
// foliage) meant to be seen through, which an opaque surface would show as holes.
bool is_cut_out(const std::vector<uint8_t>& bytes, int channels) {
  size_t clear = 0, pixels = bytes.size() / channels;
  for (size_t p = 0; p < pixels; ++p) clear += bytes[p * channels + 3] < 128 ? 1 : 0;
  return clear * 100 > pixels;
}

// Loads `path` as linear RGB (grey images repeated); false when the file cannot be read,
// is too small, too large or too elongated to tile a surface, or is a cut-out.
bool load_texture(const fs::path& path, Texture* out) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    OIIO::geterror();  // clear the message: the next candidate is tried instead
    return false;
  }
  const OIIO::ImageSpec spec = in->spec();
  const int w = spec.width, h = spec.height;
  const int channels = spec.nchannels >= 4 && spec.alpha_channel == 3 ? 4 : std::min(spec.nchannels, 3);
  // Above 8192 a side the decoded image alone would take gigabytes.
  if (w < 8 || h < 8 || w > 8192 || h > 8192 || w > 8 * h || h > 8 * w || channels < 1) {
    return false;
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(w) * h * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, bytes.data())) {
    in->geterror();
    return false;
  }
  if (channels == 4 && is_cut_out(bytes, channels)) return false;
  static const std::array<float, 256> lut = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(i);
    return t;
  }();
  std::vector<float> rgb(static_cast<size_t>(w) * h * 3);
  for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p) {
    for (int c = 0; c < 3; ++c) {
      rgb[p * 3 + c] = lut[bytes[p * channels + (channels >= 3 ? c : 0)]];
    }
  }
  *out = Texture(w, h, rgb);
  return true;
}

// Loads textures on first use and remembers which candidate each class reached.
class TexturePicker {
 public:
  TexturePicker(const fs::path& dir, std::vector<std::string> files, uint32_t seed, Scene* scene)
      : dir_(dir), files_(std::move(files)), seed_(seed), scene_(scene) {}

  // Index into scene->textures of the next image for class `c`: its own candidates first,
  // then any usable image; -1 if none loads.
  int next(TextureClass c) {
    auto& state = classes_[c];
    if (state.candidates.empty()) {
      state.candidates = texture_candidates(files_, c, seed_);
      const std::vector<std::string> others = usable_textures(files_, seed_);
      state.fallback = others.size() != state.candidates.size() ? others : std::vector<std::string>{};
    }
    for (auto* list : {&state.candidates, &state.fallback}) {
      const size_t n = list->size();
      for (size_t tried = 0; tried < n; ++tried) {
        const int index = load((*list)[state.cursor++ % n]);
        if (index >= 0) return index;
      }
    }
    return -1;
  }

 private:
  struct ClassState {
    std::vector<std::string> candidates, fallback;
    size_t cursor = 0;
  };

  int load(const std::string& name) {
    const auto known = loaded_.find(name);
    if (known != loaded_.end()) return known->second;
    Texture texture;
    int index = -1;
    if (load_texture(dir_ / name, &texture)) {
      index = static_cast<int>(scene_->textures.size());
      scene_->textures.push_back(std::move(texture));
      scene_->texture_names.push_back(name);
    }
    loaded_[name] = index;
    return index;
  }

  fs::path dir_;
  std::vector<std::string> files_;
  uint32_t seed_;
  Scene* scene_;
  std::map<TextureClass, ClassState> classes_;
  std::map<std::string, int> loaded_;
};

}  // namespace

const char* texture_class_name(TextureClass c) {
  switch (c) {
    case TextureClass::kBrick: return "brick";
    case TextureClass::kConcrete: return "concrete";
    case TextureClass::kWood: return "wood";
    case TextureClass::kMetal: return "metal";
    case TextureClass::kTile: return "tile";
    case TextureClass::kWall: return "wall";
    case TextureClass::kCeiling: return "ceiling";
    case TextureClass::kGrass: return "grass";
    case TextureClass::kSky: return "sky";
    case TextureClass::kPaving: return "paving";
    case TextureClass::kFabric: return "fabric";
    case TextureClass::kLeaves: return "leaves";
    case TextureClass::kWindow: return "window";
  }
  return "unknown";
}

const std::vector<std::string>& texture_class_words(TextureClass c) {
  static const std::map<TextureClass, std::vector<std::string>> words = {
      {TextureClass::kBrick, {"brick", "block"}},
      {TextureClass::kConcrete, {"concrete", "cement", "crete", "stone"}},
      {TextureClass::kWood, {"wood", "plank", "crate"}},
      {TextureClass::kMetal, {"metal", "steel", "iron", "rusty"}},
      {TextureClass::kTile, {"tile", "floor"}},
      {TextureClass::kWall, {"wall", "plaster"}},
      {TextureClass::kCeiling, {"ceil", "roof", "panel"}},
      {TextureClass::kGrass, {"grass", "dirt", "ground", "terrain"}},
      {TextureClass::kSky, {"sky", "skies", "cloud"}},
      {TextureClass::kPaving, {"street", "pave", "cobble", "asphalt", "road", "sidewalk"}},
      {TextureClass::kFabric, {"carpet", "textil", "fabric", "cloth", "couch", "seat", "rug"}},
      {TextureClass::kLeaves, {"leaves", "leaf", "hedge", "bush", "foliage", "jungle"}},
      {TextureClass::kWindow, {"window", "glass"}},
  };
  return words.at(c);
}

Result<std::vector<std::string>> list_texture_files(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    return Status(ErrorCode::kNotFound, "texture folder " + dir.string() + " does not exist or is not a folder");
  }
  std::vector<std::string> files;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
  for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    // Hidden entries (".staging", ".DS_Store") are no part of the set.
    if (it->path().filename().string().starts_with(".")) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file(ec)) continue;
    const std::string ext = lower(it->path().extension().string());
    if (std::find(kImageExtensions.begin(), kImageExtensions.end(), ext) == kImageExtensions.end()) continue;
    files.push_back(it->path().lexically_relative(dir).generic_string());
  }
  if (ec) return Status(ErrorCode::kIoError, "cannot list texture folder " + dir.string() + ": " + ec.message());
  if (files.empty()) {
    return Status(ErrorCode::kInvalidArgument,
                  "texture folder " + dir.string() + " holds no images (jpg, jpeg, tga, png, bmp, tif)");
  }
  std::sort(files.begin(), files.end());
  return files;
}

namespace {

// Neither a skipped layer (light map, glow, trim, ...) nor a surface map.
bool is_usable(const std::string& name) {
  return !contains_any(lower(name), kTextureSkipWords) && !is_surface_map(name);
}

bool has_class_word(const std::vector<std::string>& files, TextureClass c) {
  return std::any_of(files.begin(), files.end(), [c](const std::string& name) {
    return is_usable(name) && contains_any(lower(name), texture_class_words(c));
  });
}

}  // namespace

std::vector<std::string> usable_textures(const std::vector<std::string>& files, uint32_t seed) {
  std::vector<std::string> out;
  for (const std::string& name : files) {
    if (is_usable(name)) out.push_back(name);
  }
  std::stable_sort(out.begin(), out.end(), [seed](const std::string& a, const std::string& b) {
    return name_hash(a, seed) < name_hash(b, seed);
  });
  return out;
}

std::vector<std::string> texture_candidates(const std::vector<std::string>& files, TextureClass c, uint32_t seed) {
  const std::vector<std::string> usable = usable_textures(files, seed);
  std::vector<std::string> matching;
  for (const std::string& name : usable) {
    if (contains_any(lower(name), texture_class_words(c))) matching.push_back(name);
  }
  return matching.empty() ? usable : matching;
}

Status apply_photo_textures(const fs::path& dir, uint32_t seed, double texture_scale, Scene* scene) {
  SVC_ASSIGN_OR_RETURN(std::vector<std::string> files, list_texture_files(dir));
  const bool has_sky_image = has_class_word(files, TextureClass::kSky);
  TexturePicker picker(dir, std::move(files), seed, scene);
  const auto no_image = [&](TextureClass c) {
    return Status(ErrorCode::kInvalidArgument, "texture folder " + dir.string() + " has no usable image for " +
                                                   texture_class_name(c) +
                                                   " surfaces (none decodes as an image of "
                                                   "at least 8x8 pixels outside the skipped "
                                                   "light map, glow, blend and trim layers)");
  };
  for (Material& m : scene->materials) {
    const TextureClass c = class_of(m.pattern);
    m.texture = picker.next(c);
    if (m.texture < 0) return no_image(c);
    m.texture_metres = repeat_metres(c) * texture_scale;
    const double mean = luminance(scene->textures[m.texture].mean());
    m.texture_gain = std::clamp(luminance(m.base) / std::max(mean, 1e-4), 0.5, 2.5);
  }
  // A folder without sky images (no file named for the sky) keeps the procedural clouds:
  // a wall or floor image over the sky would look like nothing real.
  if (!has_sky_image) return Status::Ok();
  scene->sky_texture = picker.next(TextureClass::kSky);
  if (scene->sky_texture < 0) return no_image(TextureClass::kSky);
  const double sky_mean = luminance(scene->textures[scene->sky_texture].mean());
  scene->sky_texture_gain = std::clamp(0.6 / std::max(sky_mean, 1e-4), 0.5, 3.0);
  return Status::Ok();
}

}  // namespace svc::samples::detail
