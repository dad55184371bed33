// SPDX-License-Identifier: BSD-2-Clause
// Photographic materials: images from a folder, chosen per material class by file name,
// replacing the procedural patterns of a built Scene. Internal to svc_scene.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene_layout.h"
#include "svc/status.h"

namespace svc::samples::detail {

// Image files (jpg, jpeg, tga, png, bmp, tif, tiff) under `dir`, recursively, as paths
// relative to it with '/' separators, sorted bytewise. kNotFound naming `dir` when it is
// missing or not a folder; kInvalidArgument naming it when it holds no image file.
Result<std::vector<std::string>> list_texture_files(const std::filesystem::path& dir);

// Words in a file's relative path that make it a candidate for each material class;
// names with a word of kTextureSkipWords (light maps, glow and blend layers, trims) and
// the normal, specular, gloss and height maps ("_nm", "_sm", "_gm", "_hm" before the
// extension) are never chosen.
enum class TextureClass : uint8_t {
  kBrick,
  kConcrete,
  kWood,
  kMetal,
  kTile,
  kWall,
  kCeiling,
  kGrass,
  kSky,
  kPaving,
  kFabric,
  kLeaves,
  kWindow,
};
const char* texture_class_name(TextureClass c);
const std::vector<std::string>& texture_class_words(TextureClass c);
extern const std::vector<std::string> kTextureSkipWords;

// The files no skip word rules out, ordered by a hash of the name and `seed`.
std::vector<std::string> usable_textures(const std::vector<std::string>& files, uint32_t seed);

// Candidates for `c` among `files`, in the order they are tried: those whose lower-case
// path holds one of the class words (all usable files if none does), ordered by a hash
// of the name and `seed`.
std::vector<std::string> texture_candidates(const std::vector<std::string>& files, TextureClass c, uint32_t seed);

// Gives every material of `scene` and its sky an image from `dir`: the n-th material of
// a class takes the n-th candidate that loads (8 to 8192 pixels a side, aspect at most
// 8:1, not a cut-out with over 1 % of its alpha below one half), any usable image when
// none of them does. The sky takes an image only when a file is named for it (procedural
// clouds otherwise). Errors name the folder, among them one where no image loads.
// `texture_scale` multiplies the metres one repeat of each image covers.
Status apply_photo_textures(const std::filesystem::path& dir, uint32_t seed, double texture_scale, Scene* scene);

}  // namespace svc::samples::detail
