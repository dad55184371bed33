// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene_render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace svc::samples::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------- noise and filtering

inline uint32_t hash2(int32_t x, int32_t y, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B9u;
  h ^= static_cast<uint32_t>(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<uint32_t>(y) * 0xC2B2AE35u;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

inline double hash01(int32_t x, int32_t y, uint32_t seed) {
  return static_cast<double>(hash2(x, y, seed)) * (1.0 / 4294967296.0);
}

inline int32_t floor_int(double v) { return static_cast<int32_t>(std::floor(v)); }

// Smooth value noise in [0, 1) with unit lattice spacing.
double value_noise(double u, double v, uint32_t seed) {
  const double fu = std::floor(u), fv = std::floor(v);
  const int32_t iu = static_cast<int32_t>(fu), iv = static_cast<int32_t>(fv);
  double su = u - fu, sv = v - fv;
  su = su * su * su * (su * (su * 6 - 15) + 10);
  sv = sv * sv * sv * (sv * (sv * 6 - 15) + 10);
  const double a = hash01(iu, iv, seed), b = hash01(iu + 1, iv, seed);
  const double c = hash01(iu, iv + 1, seed), d = hash01(iu + 1, iv + 1, seed);
  return (a + (b - a) * su) + ((c + (d - c) * su) - (a + (b - a) * su)) * sv;
}

// Fractal sum of value noise, wavelength 1 for the first octave. Octaves finer than the
// pixel footprint `fp` (in the same units) fade to their mean, which is how a renderer's
// texture filtering removes detail it cannot resolve.
double fbm(double u, double v, uint32_t seed, int octaves, double fp) {
  double sum = 0, amp = 0.5, total = 0, freq = 1;
  for (int o = 0; o < octaves; ++o) {
    total += amp;
    const double fade = fp > 0 ? std::clamp(1.0 / (freq * fp) - 1.0, 0.0, 1.0) : 1.0;
    if (fade > 0) {
      const double n = value_noise(u * freq + o * 17.31, v * freq - o * 9.73, seed + o * 101u);
      sum += amp * (fade * n + (1 - fade) * 0.5);
    } else {
      sum += amp * 0.5;
    }
    amp *= 0.5;
    freq *= 2.03;
  }
  return sum / total;
}

// Fraction of the window [x - f/2, x + f/2] covered by lines of relative width `w`
// centred on the integers: a box-filtered grout/mortar/gap line.
double filtered_lines(double x, double w, double f) {
  x += w / 2;
  if (f < 1e-4) {
    const double fr = x - std::floor(x);
    return fr < w ? 1.0 : 0.0;
  }
  auto integral = [w](double s) {
    const double fl = std::floor(s);
    return fl * w + std::min(s - fl, w);
  };
  return std::clamp((integral(x + f / 2) - integral(x - f / 2)) / f, 0.0, 1.0);
}

// 1 while elements of `size` are well resolved, 0 once they shrink below a pixel.
inline double detail_fade(double size, double fp) {
  return fp > 0 ? std::clamp((size / fp - 1.0) * 0.5, 0.0, 1.0) : 1.0;
}

inline double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

inline Vec3 mix(const Vec3& a, const Vec3& b, double t) { return a + (b - a) * t; }

inline double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// ---------------------------------------------------------------- materials

// Albedo of `m` at surface coordinates (u, v) in metres, with pixel footprint `fp`.
Vec3 albedo(const Material& m, double u, double v, double fp) {
  const uint32_t s = m.seed;
  const double dirt = 0.86 + 0.26 * fbm(u * 0.35, v * 0.35, s + 9, 2, fp * 0.35);
  switch (m.pattern) {
    case Pattern::kTiles:
    case Pattern::kPanels: {
      const double size = m.scale;
      const double line = m.pattern == Pattern::kTiles ? 0.006 : 0.02;
      const double lu = filtered_lines(u / size, line / size, fp / size);
      const double lv = filtered_lines(v / size, line / size, fp / size);
      const double grout = 1 - (1 - lu) * (1 - lv);
      const double tint = (hash01(floor_int(u / size), floor_int(v / size), s) - 0.5) * 2;
      const double grain = fbm(u * 6, v * 6, s + 1, 3, fp * 6);
      const double speck = fbm(u * 70, v * 70, s + 2, 2, fp * 70);
      const Vec3 tile =
          m.base * (1 + m.variation * tint * detail_fade(size, fp)) * (0.84 + 0.32 * grain) * (0.9 + 0.2 * speck);
      return mix(tile, m.second, grout) * dirt;
    }
    case Pattern::kBricks: {
      const double length = m.scale, height = m.scale * 0.32, mortar = 0.011;
      const int32_t row = floor_int(v / height);
      const double uu = u + (row & 1) * length * 0.5;
      const int32_t col = floor_int(uu / length);
      const double lu = filtered_lines(uu / length, mortar / length, fp / length);
      const double lv = filtered_lines(v / height, mortar / height, fp / height);
      const double joint = 1 - (1 - lu) * (1 - lv);
      const double fade = detail_fade(height, fp);
      const double tint = (hash01(col, row, s) - 0.5) * 2 * fade;
      const double hue = (hash01(col, row, s + 5) - 0.5) * 2 * fade;
      const double grain = fbm(u * 25, v * 25, s + 1, 3, fp * 25);
      Vec3 brick = m.base * (1 + m.variation * tint) * (0.8 + 0.4 * grain);
      brick.x *= 1 + 0.12 * hue;
      brick.z *= 1 - 0.12 * hue;
      const Vec3 mortar_color = m.second * (0.85 + 0.3 * fbm(u * 40, v * 40, s + 3, 2, fp * 40));
      return mix(brick, mortar_color, joint) * dirt;
    }
    case Pattern::kPlanks: {
      const double width = m.scale, length = m.scale * 8;
      const int32_t row = floor_int(v / width);
      const double uu = u + hash01(row, 7, s) * length;
      const int32_t idx = floor_int(uu / length);
      const double gap = 0.004;
      const double lv = filtered_lines(v / width, gap / width, fp / width);
      const double lu = filtered_lines(uu / length, gap / length, fp / length);
      const double joint = 1 - (1 - lu) * (1 - lv);
      const double fade = detail_fade(width, fp);
      const double tint = (hash01(idx, row, s) - 0.5) * 2 * fade;
      const double grain_v = v * 30 + idx * 13.7;
      const double warp = fbm(uu * 0.8, grain_v * 0.2, s + 2, 3, fp * 6);
      const double rings = 0.5 + 0.5 * std::sin(2 * kPi * (v * 22 + warp * 3 + idx * 0.37));
      const double grain = fbm(uu * 2, grain_v, s + 1, 4, fp * 30);
      const Vec3 wood = m.base * (1 + m.variation * tint) *
                        (0.78 + 0.22 * (0.5 + (rings - 0.5) * detail_fade(0.045, fp)) + 0.25 * grain);
      return mix(wood, m.second, joint) * dirt;
    }
    case Pattern::kConcrete: {
      const double pw = m.scale, ph = m.scale * 0.5;
      const double lu = filtered_lines(u / pw, 0.008 / pw, fp / pw);
      const double lv = filtered_lines(v / ph, 0.008 / ph, fp / ph);
      const double joint = 1 - (1 - lu) * (1 - lv);
      const double tint = (hash01(floor_int(u / pw), floor_int(v / ph), s) - 0.5) * 2 * detail_fade(ph, fp);
      const double mottle = fbm(u * 0.9, v * 0.9, s + 1, 4, fp * 0.9);
      const double fine = fbm(u * 30, v * 30, s + 2, 3, fp * 30);
      const double pores = value_noise(u * 90, v * 90, s + 3);
      const double pore = smoothstep(0.82, 0.9, pores) * detail_fade(0.012, fp);
      const Vec3 c =
          m.base * (1 + m.variation * tint) * (0.78 + 0.38 * mottle) * (0.9 + 0.2 * fine) * (1 - 0.2 * pore);
      return mix(c, m.second, joint * 0.7) * dirt;
    }
    case Pattern::kPlaster: {
      const double blotch = fbm(u * 1.4, v * 1.4, s + 1, 4, fp * 1.4);
      const double grain = fbm(u * 45, v * 45, s + 2, 2, fp * 45);
      return m.base * (0.92 + 0.14 * blotch) * (0.95 + 0.1 * grain) * (0.5 + 0.5 * dirt);
    }
    case Pattern::kStripes: {
      const double period = m.scale;
      const double stripe = filtered_lines(u / period, 0.5, fp / period);
      const double pin = filtered_lines(u / period + 0.25, 0.05, fp / period);
      const double grain = fbm(u * 45, v * 45, s + 2, 2, fp * 45);
      const Vec3 c = mix(mix(m.base, m.second, stripe), m.base * 0.55, pin * 0.8);
      return c * (0.95 + 0.1 * grain) * (0.5 + 0.5 * dirt);
    }
    case Pattern::kMetal: {
      const double band = filtered_lines(u / m.scale, 0.05 / m.scale, fp / m.scale);
      const double mottle = fbm(u * 0.6, v * 2.0, s + 1, 3, fp * 2.0);
      const double brushed = fbm(u * 3, v * 90, s + 2, 2, fp * 90);
      const Vec3 c = m.base * (0.8 + 0.3 * mottle) * (0.92 + 0.16 * brushed);
      return mix(c, m.second, band) * dirt;
    }
    case Pattern::kPaving: {
      // Setts in running rows, each with its own tint, in a darker joint.
      const double width = m.scale, depth = m.scale * 0.6, joint = 0.012;
      const int32_t row = floor_int(v / depth);
      const double uu = u + (row & 1) * width * 0.5;
      const int32_t col = floor_int(uu / width);
      const double lu = filtered_lines(uu / width, joint / width, fp / width);
      const double lv = filtered_lines(v / depth, joint / depth, fp / depth);
      const double gap = 1 - (1 - lu) * (1 - lv);
      const double tint = (hash01(col, row, s) - 0.5) * 2 * detail_fade(depth, fp);
      const double grain = fbm(u * 40, v * 40, s + 1, 3, fp * 40);
      const Vec3 stone = m.base * (1 + m.variation * tint) * (0.82 + 0.36 * grain);
      return mix(stone, m.second, gap) * dirt;
    }
    case Pattern::kFabric: {
      // A weave of warp and weft threads with a slow colour variation.
      const double period = m.scale;
      const double warp = filtered_lines(u / period, 0.5, fp / period);
      const double weft = filtered_lines(v / period, 0.5, fp / period);
      const double weave = 0.5 + 0.5 * (warp - weft) * detail_fade(period, fp);
      const double mottle = fbm(u * 3, v * 3, s + 1, 3, fp * 3);
      return mix(m.base, m.second, 0.35 * weave) * (0.85 + 0.3 * mottle);
    }
    case Pattern::kLeaves: {
      const double clumps = fbm(u * 4, v * 4, s + 1, 4, fp * 4);
      const double leaf = fbm(u * 30, v * 30, s + 2, 3, fp * 30);
      return mix(m.second, m.base, smoothstep(0.3, 0.7, clumps)) * (0.6 + 0.8 * leaf);
    }
    case Pattern::kGlass: {
      // Dark panes: a faint vertical sky gradient and mullions every `scale` metres.
      const double frame = filtered_lines(u / m.scale, 0.04 / m.scale, fp / m.scale);
      const double sheen = 0.8 + 0.4 * fbm(u * 0.5, v * 2, s + 1, 2, fp * 2);
      return mix(m.base * sheen, m.second, frame);
    }
    case Pattern::kGround: {
      const double patch = fbm(u * 0.12, v * 0.12, s + 1, 4, fp * 0.12);
      const double earth = smoothstep(0.48, 0.62, patch);
      const double fine = fbm(u * 5, v * 5, s + 2, 4, fp * 5);
      return mix(m.base, m.second, earth) * (0.65 + 0.7 * fine);
    }
  }
  return m.base;
}

// ---------------------------------------------------------------- sky

const Vec3 kHorizon(0.66, 0.75, 0.86);
const Vec3 kZenith(0.16, 0.33, 0.72);

Vec3 sky_color(const Scene& scene, const Vec3& dir, double pixel_angle) {
  const double y = dir.y;
  if (y <= 0) return kHorizon * 0.92;
  Vec3 c = mix(kHorizon, kZenith, std::pow(y, 0.55));
  if (y > 0.01 && scene.sky_texture >= 0) {
    // The sky image over a plane above, fading into the horizon haze.
    constexpr double kRepeat = 1.5;  // plane units per repeat of the image
    const double scale = 0.6 / y / kRepeat;
    const double fp = pixel_angle * 0.6 / (y * y) / kRepeat;
    const Texture& texture = scene.textures[scene.sky_texture];
    const Vec3 image = texture.sample(dir.x * scale, dir.z * scale, fp);
    // Game skies are often strongly tinted: the image lends the sky its structure in
    // full but only part of its color.
    const double relative = luminance(image) / std::max(luminance(texture.mean()), 1e-4);
    const Vec3 photo = mix(c * relative, image * scene.sky_texture_gain, 0.35);
    c = mix(c, photo, 0.9 * smoothstep(0.02, 0.25, y));
  } else if (y > 0.01) {
    // A cloud layer: noise over the plane the ray meets, thinning towards the horizon.
    const double scale = 0.6 / y;
    const double u = dir.x * scale, v = dir.z * scale;
    const double fp = pixel_angle * 0.6 / (y * y);
    const double n = fbm(u, v, 4242u, 6, fp);
    const double cover = smoothstep(0.46, 0.7, n) * smoothstep(0.01, 0.15, y);
    const double shade = fbm(u * 1.7 + 3.1, v * 1.7 - 1.3, 4243u, 4, fp * 1.7);
    const Vec3 cloud = Vec3(0.95, 0.95, 0.97) * (0.72 + 0.35 * shade);
    c = mix(c, cloud, cover);
  }
  const double sun = std::max(0.0, glm::dot(dir, scene.sun_dir));
  c += Vec3(1.0, 0.9, 0.7) * (0.25 * std::pow(sun, 24.0) + 4.0 * smoothstep(0.9995, 0.9998, sun));
  return c;
}

// ---------------------------------------------------------------- shading

// Linear light to 8-bit sRGB through a soft shoulder (so that sunlit surfaces and the
// sun do not clip flat), after an exposure gain. The curve is inverted once into the 255
// linear values where the output code steps up, so a pixel costs a binary search instead
// of exp and pow.
class SrgbEncoder {
 public:
  explicit SrgbEncoder(double exposure) {
    for (int code = 1; code <= 255; ++code) {
      const double srgb = (code - 0.5) / 255.0;
      const double mapped = srgb <= 0.04045 ? srgb / 12.92 : std::pow((srgb + 0.055) / 1.055, 2.4);
      thresholds_[code - 1] = -std::log(1.0 - mapped) / exposure;
    }
  }
  uint8_t encode(double linear) const {
    return static_cast<uint8_t>(std::upper_bound(thresholds_.begin(), thresholds_.end(), linear) -
                                thresholds_.begin());
  }

 private:
  std::array<double, 255> thresholds_{};
};

// Surface coordinates in metres on a planar map chosen by the normal, or around a
// cylinder.
void surface_uv(const Primitive& prim, const Vec3& p, const Vec3& n, double* u, double* v) {
  if (prim.shape == Shape::kCylinder && std::abs(n[prim.axis]) < 0.5) {
    const int a = (prim.axis + 1) % 3, b = (prim.axis + 2) % 3;
    const double arc = std::atan2(p[b] - prim.centre_b, p[a] - prim.centre_a) * prim.radius;
    if (prim.axis == 1) {
      *u = arc;
      *v = p.y;
    } else {
      *u = p[prim.axis];
      *v = arc;
    }
    return;
  }
  const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
  if (ax >= ay && ax >= az) {
    *u = p.z;
    *v = p.y;
  } else if (ay >= az) {
    *u = p.x;
    *v = p.z;
  } else {
    *u = p.x;
    *v = p.y;
  }
}

struct Shaded {
  Vec3 color;
  double depth;  // eye z, +inf for sky
};

// The nearest surface along `ray` among `candidates` (the primitives the ray's tile can
// see, from frustum_candidates) and the ground plane outside the building.
struct Surface {
  bool found = false;
  Hit hit;                // hit.primitive -1 for the ground plane
  uint16_t material = 0;  // as the primitive or the ground gives it
};

Surface nearest_surface(const Scene& scene, const std::vector<Candidate>& candidates, const Ray& ray) {
  Surface s;
  s.found = closest_among(scene.bvh.primitives(), candidates, ray, kNearPlane, kMaxDepth, &s.hit);
  if (s.found) s.material = scene.bvh.primitives()[s.hit.primitive].material;
  if (ray.dir.y < 0) {
    const double t = (scene.ground_y - ray.origin.y) / ray.dir.y;
    if (t > kNearPlane && t < (s.found ? s.hit.t : kMaxDepth)) {
      s.found = true;
      s.hit.t = t;
      s.hit.normal = Vec3(0, 1, 0);
      s.hit.primitive = -1;
      s.material = scene.ground_material;
    }
  }
  return s;
}

// `pixel_angle`: the angle one sample covers; `anisotropic`: texture detail kept along the
// grazing direction, as a renderer's anisotropic filtering keeps it.
Shaded shade_ray(const Scene& scene, const std::vector<Candidate>& candidates, const Ray& ray, double pixel_angle,
                 bool anisotropic) {
  const Surface surface = nearest_surface(scene, candidates, ray);
  const Hit& hit = surface.hit;
  const Primitive* prim = surface.found && hit.primitive >= 0 ? &scene.bvh.primitives()[hit.primitive] : nullptr;
  uint16_t material_id = surface.material;
  const double dir_length = glm::length(ray.dir);
  const Vec3 unit_dir = ray.dir / dir_length;
  if (!surface.found) {
    return {sky_color(scene, unit_dir, pixel_angle), std::numeric_limits<double>::infinity()};
  }

  const Vec3 p = ray.origin + ray.dir * hit.t;
  Vec3 n = hit.normal;
  if (glm::dot(n, ray.dir) > 0) n = -n;
  // The room the surface faces decides room-dependent materials, light and ambient.
  const Vec3 probe = p + n * 0.05;
  const int room_index = scene.room_at(probe.x, probe.z);
  const Room* room = room_index >= 0 && room_index < static_cast<int>(scene.rooms.size()) ? &scene.rooms[room_index]
                                                                                          : nullptr;
  if (material_id >= kRoomWall) {
    if (room == nullptr) {
      material_id = scene.exterior_wall;
    } else if (material_id == kRoomWall) {
      material_id = room->wall;
    } else if (material_id == kRoomFloor) {
      material_id = room->floor;
    } else {
      material_id = room->ceiling;
    }
  }
  const Material& material = scene.materials[material_id];

  double u, v;
  if (prim != nullptr) {
    surface_uv(*prim, p, n, &u, &v);
  } else {
    u = p.x;
    v = p.z;
  }
  // Footprint of a pixel on the surface: grows with depth and with grazing angles.
  const double cos_incidence = std::max(0.2, std::abs(glm::dot(n, unit_dir)));
  const double fp = hit.t * pixel_angle / (anisotropic ? std::sqrt(cos_incidence) : cos_incidence);
  Vec3 base = material.texture < 0 ? albedo(material, u, v, fp)
                                   : scene.textures[material.texture].sample(u / material.texture_metres,
                                                                             v / material.texture_metres,
                                                                             fp / material.texture_metres) *
                                         material.texture_gain;
  // Skirting boards along the foot of house walls.
  if (scene.kind == SceneKind::kHouse && room != nullptr && std::abs(n.y) < 0.5 && p.y < 0.1 && p.y > 0.0) {
    base = Vec3(0.55, 0.52, 0.47) * (0.9 + 0.1 * fbm(u * 20, v * 20, 77u, 2, fp * 20));
  }

  // Sky light from above, bounce light from below; dimmer indoors and near the floor.
  const bool indoors = room != nullptr;
  double ambient =
      indoors ? (room->ambient > 0 && scene.kind == SceneKind::kHouse ? room->ambient : scene.ambient_indoor)
              : scene.ambient_outdoor;
  ambient *= 0.75 + 0.25 * smoothstep(0.0, 1.2, p.y);
  const Vec3 sky_light(0.78, 0.86, 1.0), bounce_light(0.5, 0.46, 0.4);
  Vec3 light = mix(bounce_light, sky_light, 0.5 + 0.5 * n.y) * ambient;

  const Vec3 offset_origin = p + n * 1e-5;
  const double sun_ndl = glm::dot(n, scene.sun_dir);
  if (sun_ndl > 0) {
    const Ray shadow = make_ray(offset_origin, scene.sun_dir);
    if (!scene.bvh.occluded(shadow, 1e-5, 1e4)) light += scene.sun_color * sun_ndl;
  }
  if (room != nullptr && room->has_lamp) {
    const Vec3 to_lamp = room->lamp - p;
    const double dist2 = glm::dot(to_lamp, to_lamp);
    const double ndl = glm::dot(n, to_lamp) / std::sqrt(dist2);
    if (ndl > 0) {
      const Ray shadow = make_ray(offset_origin, to_lamp);
      if (!scene.bvh.occluded(shadow, 1e-5, 1.0)) {
        light += Vec3(1.0, 0.86, 0.66) * (2.2 * ndl / (dist2 + 0.4));
      }
    }
  }

  Vec3 color = base * light;
  // Aerial haze: distant ground blends into the horizon color where it meets the sky.
  const double distance = hit.t * dir_length;
  if (distance > 2.0) {  // below 2 m the haze is under 0.2 %
    const double haze = 1 - std::exp(-(distance / 45.0) * (distance / 45.0));
    color = mix(color, kHorizon * 0.92, haze);
  }
  return {color, hit.t};
}

}  // namespace

glm::dmat4 face_view_matrix(const Vec3& eye, int face) {
  static const Vec3 kForward[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const Vec3 kUp[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  return glm::lookAt(eye, eye + kForward[face], kUp[face]);
}

Vec3 sample_ray_direction(const glm::dmat4& view, int size, double x, double y) {
  const Vec3 right(view[0][0], view[1][0], view[2][0]);
  const Vec3 up(view[0][1], view[1][1], view[2][1]);
  const Vec3 back(view[0][2], view[1][2], view[2][2]);
  // tan(fov/2) = 1 for the 90-degree cube faces.
  return right * (x / size * 2 - 1) + up * (1 - y / size * 2) - back;
}

Vec3 pixel_ray_direction(const glm::dmat4& view, int size, int i, int j) {
  return sample_ray_direction(view, size, i + 0.5, j + 0.5);
}

namespace {

// Colour of pixel (i, j) as the mean of an n x n grid of samples in linear light, and
// its depth from the one ray through the pixel centre.
Shaded render_pixel(const Scene& scene, const std::vector<Candidate>& candidates, const Vec3& eye,
                    const glm::dmat4& view, int size, const RenderSettings& settings, int i, int j) {
  const double pixel_angle = 2.0 / size;
  const bool aniso = settings.anisotropic;
  const int n = settings.supersample;
  if (n == 1)
    return shade_ray(scene, candidates, make_ray(eye, pixel_ray_direction(view, size, i, j)), pixel_angle, aniso);
  Vec3 sum(0.0);
  for (int sy = 0; sy < n; ++sy) {
    for (int sx = 0; sx < n; ++sx) {
      const Vec3 dir = sample_ray_direction(view, size, i + (sx + 0.5) / n, j + (sy + 0.5) / n);
      sum += shade_ray(scene, candidates, make_ray(eye, dir), pixel_angle / n, aniso).color;
    }
  }
  const Surface centre = nearest_surface(scene, candidates, make_ray(eye, pixel_ray_direction(view, size, i, j)));
  return {sum / static_cast<double>(n * n), centre.found ? centre.hit.t : std::numeric_limits<double>::infinity()};
}

}  // namespace

void render_face(const Scene& scene, const Vec3& eye, const glm::dmat4& view, int size,
                 const RenderSettings& settings, uint8_t* rgb, float* depth) {
  const SrgbEncoder encoder(kBaseExposure * std::exp2(settings.exposure_stops));
  // Tiles of pixels share one list of the primitives their pyramid of rays can meet: the
  // pyramid through the tile's outer corners, which holds every sample ray of its pixels.
  constexpr int kTile = 16;
  std::vector<Candidate> candidates;
  candidates.reserve(scene.bvh.primitives().size());
  for (int tj = 0; tj < size; tj += kTile) {
    for (int ti = 0; ti < size; ti += kTile) {
      const int i1 = std::min(ti + kTile, size) - 1, j1 = std::min(tj + kTile, size) - 1;
      const Vec3 corners[4] = {sample_ray_direction(view, size, ti, tj),
                               sample_ray_direction(view, size, i1 + 1, tj),
                               sample_ray_direction(view, size, i1 + 1, j1 + 1),
                               sample_ray_direction(view, size, ti, j1 + 1)};
      frustum_candidates(scene.bvh.primitives(), eye, corners, &candidates);
      for (int j = tj; j <= j1; ++j) {
        for (int i = ti; i <= i1; ++i) {
          const Shaded s = render_pixel(scene, candidates, eye, view, size, settings, i, j);
          const size_t index = static_cast<size_t>(j) * size + i;
          rgb[index * 3 + 0] = encoder.encode(s.color.x);
          rgb[index * 3 + 1] = encoder.encode(s.color.y);
          rgb[index * 3 + 2] = encoder.encode(s.color.z);
          depth[index] = static_cast<float>(s.depth);
        }
      }
    }
  }
}

}  // namespace svc::samples::detail
