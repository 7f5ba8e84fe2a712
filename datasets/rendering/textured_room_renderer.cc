#include "datasets/rendering/textured_room_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/errors.h"
#include "core/image_codec.h"
#include "core/random.h"
#include "core/text.h"

namespace mavloc {
namespace {

constexpr int kTexturedRoomFaces = 6;
constexpr int kFacesPerBox = 6;
constexpr int kMinTextureSidePx = 32;
// Mip levels down to a top level of at least 16 texels a side; 7 levels cover footprints of 64
// texels (25 cm at 4 mm per texel), more than a 752 x 480 camera's pixel spans across the room.
constexpr int kMaxMipLevels = 7;
constexpr int kMinTopLevelPx = 16;
// A distant light and its ambient share: brightness = ambient + diffuse max(0, n . l).
constexpr double kRoomAmbient = 0.7;
constexpr double kRoomDiffuse = 0.4;
// The footprint of a pixel grows as 1 / cos(incidence); clamped so that grazing views keep some
// detail instead of taking the coarsest level.
constexpr float kMinCosIncidence = 0.25f;
// A ray the camera model undistorts is kept only if it projects back onto its pixel.
constexpr double kRayRoundTripPx = 1e-3;

bool IsImageFileName(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg";
}

bool StartsWithAero(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return name.rfind("aero", 0) == 0;
}

// A grey photograph as mip levels; empty levels with *why set when it is too small.
RoomTexture MipPyramid(const cv::Mat& image, const std::string& path, std::string* why) {
  cv::Mat gray = image;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  RoomTexture texture;
  texture.path = path;
  if (gray.type() != CV_8UC1 || std::min(gray.cols, gray.rows) < kMinTextureSidePx) {
    *why = fmt::format("{} x {} pixels, smaller than {} x {} (or not 8-bit grey or colour)",
                       gray.cols, gray.rows, kMinTextureSidePx, kMinTextureSidePx);
    return texture;
  }
  int levels = 1;
  while (levels < kMaxMipLevels && (std::min(gray.cols, gray.rows) >> levels) >= kMinTopLevelPx)
    ++levels;
  // Cropped so that each level is exactly half the one below (2x2 box averages, no resampling).
  const int crop_w = (gray.cols >> (levels - 1)) << (levels - 1);
  const int crop_h = (gray.rows >> (levels - 1)) << (levels - 1);
  cv::Mat base;
  gray(cv::Rect(0, 0, crop_w, crop_h)).convertTo(base, CV_32F);
  texture.levels.push_back(base);
  for (int k = 1; k < levels; ++k) {
    const cv::Mat& below = texture.levels.back();
    cv::Mat half;
    cv::resize(below, half, cv::Size(below.cols / 2, below.rows / 2), 0, 0, cv::INTER_AREA);
    texture.levels.push_back(half);
  }
  return texture;
}

void AddTexture(const cv::Mat& image, const std::string& name, RoomTextures* out) {
  std::string why;
  RoomTexture texture = MipPyramid(image, name, &why);
  if (texture.levels.empty())
    out->skipped.push_back(name + ": " + why);
  else
    out->textures.push_back(std::move(texture));
}

// floor(x) as an int for the texture coordinates' range (|x| < 2^30).
inline int FloorToInt(float x) {
  const int i = static_cast<int>(x);
  return i - (x < static_cast<float>(i) ? 1 : 0);
}

// The nearest surface along o + t d, t > 0, from inside the room: the face the ray leaves the
// room through, or a box face it enters first. inv = 1 / d per axis (+-huge for d = 0).
template <typename T>
void NearestTexturedFace(const T* o, const T* d, const T* inv, const T* room_min, const T* room_max,
                         const T* boxes, int box_count, T* t_best, int* face) {
  *t_best = std::numeric_limits<T>::max();
  *face = -1;
  for (int a = 0; a < 3; ++a) {
    const bool positive = d[a] > T(0);
    const T t = ((positive ? room_max[a] : room_min[a]) - o[a]) * inv[a];
    if (t < *t_best) {
      *t_best = t;
      *face = 2 * a + (positive ? 1 : 0);
    }
  }
  for (int b = 0; b < box_count; ++b) {
    const T* lo = boxes + 6 * b;
    const T* hi = lo + 3;
    T t_near = -std::numeric_limits<T>::max(), t_far = std::numeric_limits<T>::max();
    int near_axis = 0;
    for (int a = 0; a < 3; ++a) {
      const T t1 = (lo[a] - o[a]) * inv[a], t2 = (hi[a] - o[a]) * inv[a];
      const T entry = std::min(t1, t2), exit = std::max(t1, t2);
      if (entry > t_near) {
        t_near = entry;
        near_axis = a;
      }
      t_far = std::min(t_far, exit);
    }
    if (t_near <= t_far && t_near > T(0) && t_near < *t_best) {
      *t_best = t_near;
      // A ray entering along +axis enters through the box's min side (face 2a).
      *face = kTexturedRoomFaces + kFacesPerBox * b + 2 * near_axis + (d[near_axis] > T(0) ? 0 : 1);
    }
  }
}

template <typename T>
T SafeInverse(T d) {
  constexpr T kHuge = T(1e30);
  if (std::abs(d) < T(1e-20)) return d < T(0) ? -kHuge : kHuge;
  return T(1) / d;
}

TexturedFace MakeFace(int axis, double plane, const Eigen::Vector3d& n_W, const Eigen::Vector3d& lo,
                      const Eigen::Vector3d& hi) {
  TexturedFace face;
  face.normal_axis = axis;
  face.plane = plane;
  face.n_W = n_W;
  face.e_u_W =
      axis == 2 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d(Eigen::Vector3d::UnitZ().cross(n_W));
  face.e_v_W = face.e_u_W.cross(n_W);
  // The corner of smallest (e_u, e_v): per axis, lo where the axis points up, hi where down.
  for (int k = 0; k < 3; ++k) {
    const double along = face.e_u_W[k] + face.e_v_W[k];
    face.origin_W[k] = k == axis ? plane : (along >= 0.0 ? lo[k] : hi[k]);
  }
  const Eigen::Vector3d light_W = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
  face.brightness = kRoomAmbient + kRoomDiffuse * std::max(0.0, n_W.dot(light_W));
  return face;
}

// Textures for faces: the floor and ceiling take the aerial photographs when there are any.
void AssignTextures(const RoomTextures& textures, std::vector<TexturedFace>* faces) {
  std::vector<int> aerial, other;
  for (size_t i = 0; i < textures.textures.size(); ++i)
    (StartsWithAero(textures.textures[i].path) ? aerial : other).push_back(static_cast<int>(i));
  if (other.empty()) other = aerial;
  int next = 0;
  for (size_t k = 0; k < faces->size(); ++k) {
    const bool floor_or_ceiling = k == 4 || k == 5;
    if (floor_or_ceiling && !aerial.empty())
      (*faces)[k].texture = aerial[(k - 4) % aerial.size()];
    else if (!other.empty())
      (*faces)[k].texture = other[next++ % other.size()];
  }
}

}  // namespace

RoomTextures LoadRoomTextures(const std::string& folder, const std::string& setting) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(folder, error))
    throw InputError(folder, 0, setting, "no such folder (a folder of PNG or JPEG photographs)");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder, error))
    if (IsImageFileName(entry.path()) && entry.is_regular_file(error))
      files.push_back(entry.path());
  if (error) throw InputError(folder, 0, setting, "cannot list the folder: " + error.message());
  std::sort(files.begin(), files.end());
  RoomTextures out;
  for (const fs::path& file : files) {
    const std::string bytes = ReadWholeFile(file.string());
    std::string why = "cannot be read";
    const cv::Mat image =
        bytes.empty() ? cv::Mat() : DecodeImage(bytes, ImageDecodeMode::kGray8, &why);
    if (image.empty())
      out.skipped.push_back(file.string() + ": " + why);
    else
      AddTexture(image, file.string(), &out);
  }
  if (out.textures.empty()) {
    std::string detail = files.empty() ? "no .png, .jpg or .jpeg file" : "no usable image";
    for (const std::string& skipped : out.skipped) detail += "; " + skipped;
    throw InputError(folder, 0, setting, detail + " (textures need PNG or JPEG photographs)");
  }
  return out;
}

RoomTextures RoomTexturesFromImages(const std::vector<cv::Mat>& images,
                                    const std::vector<std::string>& names) {
  RoomTextures out;
  for (size_t i = 0; i < images.size(); ++i)
    AddTexture(images[i], i < names.size() ? names[i] : fmt::format("image {}", i), &out);
  return out;
}

std::vector<TexturedFace> TexturedRoomFaces(const TexturedRoom& room,
                                            const RoomTextures& textures) {
  std::vector<TexturedFace> faces;
  for (int a = 0; a < 3; ++a) {
    for (int side = 0; side < 2; ++side) {
      // Room faces are seen from inside: the normal points into the room.
      Eigen::Vector3d n_W = Eigen::Vector3d::Zero();
      n_W[a] = side == 0 ? 1.0 : -1.0;
      faces.push_back(
          MakeFace(a, side == 0 ? room.min_W[a] : room.max_W[a], n_W, room.min_W, room.max_W));
    }
  }
  for (size_t b = 0; b < room.boxes.size(); ++b) {
    const TexturedBox& box = room.boxes[b];
    for (int a = 0; a < 3; ++a) {
      for (int side = 0; side < 2; ++side) {
        Eigen::Vector3d n_W = Eigen::Vector3d::Zero();
        n_W[a] = side == 0 ? -1.0 : 1.0;  // outwards
        TexturedFace face =
            MakeFace(a, side == 0 ? box.min_W[a] : box.max_W[a], n_W, box.min_W, box.max_W);
        face.box = static_cast<int>(b);
        faces.push_back(face);
      }
    }
  }
  AssignTextures(textures, &faces);
  return faces;
}

Eigen::Vector3d TexelToWorld(const TexturedFace& face, double x_texel, double y_texel,
                             double texel_m) {
  return face.origin_W + texel_m * (x_texel * face.e_u_W + y_texel * face.e_v_W);
}

void TexturedRoomToMapParameters(const TexturedRoom& room,
                                 std::map<std::string, double>* parameters) {
  auto& p = *parameters;
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    p[fmt::format("textured_room_min_{}", axes[a])] = room.min_W[a];
    p[fmt::format("textured_room_max_{}", axes[a])] = room.max_W[a];
  }
  p["textured_room_texel_m"] = room.texel_m;
  p["textured_box_count"] = static_cast<double>(room.boxes.size());
  for (size_t b = 0; b < room.boxes.size(); ++b) {
    for (int a = 0; a < 3; ++a) {
      p[fmt::format("textured_box_{}_min_{}", b, axes[a])] = room.boxes[b].min_W[a];
      p[fmt::format("textured_box_{}_max_{}", b, axes[a])] = room.boxes[b].max_W[a];
    }
  }
}

TexturedRoomRenderer::TexturedRoomRenderer(const CameraModel& camera, const TexturedRoom& room,
                                           std::shared_ptr<const RoomTextures> textures,
                                           const TexturedRenderOptions& options)
    : camera_(camera), room_(room), textures_(std::move(textures)), options_(options) {
  if (!textures_ || textures_->textures.empty())
    throw std::invalid_argument("TexturedRoomRenderer: no textures");
  if (!(room_.texel_m > 0.0) || !(room_.max_W.array() > room_.min_W.array()).all())
    throw std::invalid_argument("TexturedRoomRenderer: texel_m > 0 and max_W > min_W needed");
  inv_texel_m_ = static_cast<float>(1.0 / room_.texel_m);
  faces_ = TexturedRoomFaces(room_, *textures_);
  for (const TexturedFace& face : faces_) {
    FaceLookup lookup{};
    for (int k = 0; k < 3; ++k) {
      lookup.origin[k] = static_cast<float>(face.origin_W[k]);
      lookup.u_per_m[k] = static_cast<float>(face.e_u_W[k] / room_.texel_m);
      lookup.v_per_m[k] = static_cast<float>(face.e_v_W[k] / room_.texel_m);
    }
    lookup.gain = static_cast<float>(face.brightness * options_.gain);
    lookup.texture = face.texture;
    lookups_.push_back(lookup);
  }
  for (const RoomTexture& texture : textures_->textures) {
    std::vector<Level> levels;
    for (const cv::Mat& image : texture.levels) {
      Level level;
      level.pixels = image.ptr<float>(0);
      level.width = image.cols;
      level.height = image.rows;
      level.stride = image.step1();
      level.inv_period_x = 1.0f / (2.0f * static_cast<float>(level.width));
      level.inv_period_y = 1.0f / (2.0f * static_cast<float>(level.height));
      // Mirrored repetition: period 2 x size, one entry more for the right/lower neighbour.
      for (int i = 0; i <= 2 * level.width; ++i) {
        const int r = i % (2 * level.width);
        level.mirror_x.push_back(r < level.width ? r : 2 * level.width - 1 - r);
      }
      for (int i = 0; i <= 2 * level.height; ++i) {
        const int r = i % (2 * level.height);
        level.mirror_y.push_back(r < level.height ? r : 2 * level.height - 1 - r);
      }
      levels.push_back(std::move(level));
    }
    levels_.push_back(std::move(levels));
  }
  for (const TexturedBox& box : room_.boxes) {
    for (int k = 0; k < 3; ++k) boxes_.push_back(static_cast<float>(box.min_W[k]));
    for (int k = 0; k < 3; ++k) boxes_.push_back(static_cast<float>(box.max_W[k]));
  }
  PrecomputeRays();
}

// The unit ray of every pixel centre and its angular size (the larger of the angles to the next
// pixel along u and along v: the footprint that picks the mip level).
void TexturedRoomRenderer::PrecomputeRays() {
  const int width = camera_.width(), height = camera_.height();
  rays_C_.assign(3 * static_cast<size_t>(width) * height, 0.0f);
  pixel_angle_rad_.assign(static_cast<size_t>(width) * height, 0.0f);
  std::vector<Eigen::Vector3d> rays(static_cast<size_t>(width) * height, Eigen::Vector3d::Zero());
  std::vector<char> valid(rays.size(), 0);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector2d uv(u, v);
      const auto ray = camera_.Unproject(uv);
      if (!ray) continue;
      const auto back = camera_.Project(*ray);
      if (!back || (*back - uv).norm() > kRayRoundTripPx) continue;
      const size_t i = static_cast<size_t>(v) * width + u;
      rays[i] = *ray;
      valid[i] = 1;
    }
  }
  const double fallback = 1.0 / std::max(camera_.fu(), camera_.fv());
  invalid_pixels_ = 0;
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const size_t i = static_cast<size_t>(v) * width + u;
      if (!valid[i]) {
        ++invalid_pixels_;
        continue;
      }
      // Chord to a valid neighbour (forward, else backward) along each image axis.
      auto neighbour_angle = [&](int du, int dv) {
        for (const int s : {1, -1}) {
          const int nu = u + s * du, nv = v + s * dv;
          if (nu < 0 || nv < 0 || nu >= width || nv >= height) continue;
          const size_t j = static_cast<size_t>(nv) * width + nu;
          if (valid[j]) return (rays[j] - rays[i]).norm();
        }
        return fallback;
      };
      const double angle = std::max(neighbour_angle(1, 0), neighbour_angle(0, 1));
      for (int k = 0; k < 3; ++k) rays_C_[3 * i + k] = static_cast<float>(rays[i][k]);
      pixel_angle_rad_[i] = static_cast<float>(angle);
    }
  }
}

// Bilinear sample of one level at its continuous coordinate (x, y), mirrored repetition.
float TexturedRoomRenderer::SampleLevel(const Level& level, float x, float y) {
  const float period_x = 2.0f * static_cast<float>(level.width);
  const float period_y = 2.0f * static_cast<float>(level.height);
  x -= 0.5f;  // texel centres at i + 0.5
  y -= 0.5f;
  x -= period_x * static_cast<float>(FloorToInt(x * level.inv_period_x));
  y -= period_y * static_cast<float>(FloorToInt(y * level.inv_period_y));
  int ix = std::clamp(FloorToInt(x), 0, 2 * level.width - 1);
  int iy = std::clamp(FloorToInt(y), 0, 2 * level.height - 1);
  const float fx = std::clamp(x - static_cast<float>(ix), 0.0f, 1.0f);
  const float fy = std::clamp(y - static_cast<float>(iy), 0.0f, 1.0f);
  const float* row0 = level.pixels + level.stride * level.mirror_y[iy];
  const float* row1 = level.pixels + level.stride * level.mirror_y[iy + 1];
  const int x0 = level.mirror_x[ix], x1 = level.mirror_x[ix + 1];
  const float top = row0[x0] + fx * (row0[x1] - row0[x0]);
  const float bottom = row1[x0] + fx * (row1[x1] - row1[x0]);
  return top + fy * (bottom - top);
}

// Trilinear: the two levels around log2(footprint in texels), blended.
float TexturedRoomRenderer::Shade(int face, const float* p_W, float footprint_m) const {
  const FaceLookup& f = lookups_[face];
  const float dx = p_W[0] - f.origin[0], dy = p_W[1] - f.origin[1], dz = p_W[2] - f.origin[2];
  const float x = dx * f.u_per_m[0] + dy * f.u_per_m[1] + dz * f.u_per_m[2];
  const float y = dx * f.v_per_m[0] + dy * f.v_per_m[1] + dz * f.v_per_m[2];
  const std::vector<Level>& levels = levels_[f.texture];
  const float lod = std::log2(std::max(footprint_m * inv_texel_m_, 1e-6f));
  if (lod <= 0.0f) return f.gain * SampleLevel(levels[0], x, y);
  const int top = static_cast<int>(levels.size()) - 1;
  const int l0 = static_cast<int>(lod);
  if (l0 >= top) {
    const float scale = std::ldexp(1.0f, -top);
    return f.gain * SampleLevel(levels[top], x * scale, y * scale);
  }
  const float scale0 = std::ldexp(1.0f, -l0);
  const float a = SampleLevel(levels[l0], x * scale0, y * scale0);
  const float b = SampleLevel(levels[l0 + 1], 0.5f * x * scale0, 0.5f * y * scale0);
  return f.gain * (a + (lod - static_cast<float>(l0)) * (b - a));
}

void TexturedRoomRenderer::RenderRows(const Pose& T_W_C, int row_begin, int row_end, float weight,
                                      cv::Mat* accumulator) const {
  const Eigen::Matrix3f R_W_C = T_W_C.R().cast<float>();
  const float o[3] = {static_cast<float>(T_W_C.p.x()), static_cast<float>(T_W_C.p.y()),
                      static_cast<float>(T_W_C.p.z())};
  const float room_min[3] = {static_cast<float>(room_.min_W.x()),
                             static_cast<float>(room_.min_W.y()),
                             static_cast<float>(room_.min_W.z())};
  const float room_max[3] = {static_cast<float>(room_.max_W.x()),
                             static_cast<float>(room_.max_W.y()),
                             static_cast<float>(room_.max_W.z())};
  const int box_count = static_cast<int>(room_.boxes.size());
  const int width = camera_.width();
  for (int v = row_begin; v < row_end; ++v) {
    float* out = accumulator->ptr<float>(v);
    for (int u = 0; u < width; ++u) {
      const size_t i = static_cast<size_t>(v) * width + u;
      const float angle = pixel_angle_rad_[i];
      if (angle == 0.0f) continue;
      const Eigen::Map<const Eigen::Vector3f> ray_C(&rays_C_[3 * i]);
      const Eigen::Vector3f d_W = R_W_C * ray_C;
      const float d[3] = {d_W.x(), d_W.y(), d_W.z()};
      const float inv[3] = {SafeInverse(d[0]), SafeInverse(d[1]), SafeInverse(d[2])};
      float t = 0.0f;
      int face = -1;
      NearestTexturedFace(o, d, inv, room_min, room_max, boxes_.data(), box_count, &t, &face);
      if (face < 0 || !(t > 0.0f)) continue;
      const float p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
      const float cos_incidence = std::max(std::abs(d[faces_[face].normal_axis]), kMinCosIncidence);
      out[u] += weight * Shade(face, p, t * angle / cos_incidence);
    }
  }
}

cv::Mat TexturedRoomRenderer::RenderIdeal(const std::vector<Pose>& T_W_C) const {
  cv::Mat image(camera_.height(), camera_.width(), CV_32F, cv::Scalar(0.0f));
  if (T_W_C.empty()) return image;
  const float weight = 1.0f / static_cast<float>(T_W_C.size());
  // Rows in stripes of 16: each pixel is written by one thread, the poses summed in order, so the
  // image does not depend on the number of threads.
  for (const Pose& pose : T_W_C) {
    cv::parallel_for_(cv::Range(0, (camera_.height() + 15) / 16), [&](const cv::Range& stripes) {
      RenderRows(pose, 16 * stripes.start, std::min(camera_.height(), 16 * stripes.end), weight,
                 &image);
    });
  }
  return image;
}

cv::Mat TexturedRoomRenderer::Render(const std::vector<Pose>& T_W_C, uint64_t noise_seed) const {
  const cv::Mat ideal = RenderIdeal(T_W_C);
  cv::Mat image(ideal.size(), CV_8U);
  Rng rng(noise_seed);
  const double sigma = options_.noise_sigma_grey;
  for (int v = 0; v < ideal.rows; ++v) {
    const float* in = ideal.ptr<float>(v);
    uint8_t* out = image.ptr<uint8_t>(v);
    for (int u = 0; u < ideal.cols; ++u) {
      const double value = sigma > 0.0 ? in[u] + sigma * rng.Gaussian() : in[u];
      out[u] = static_cast<uint8_t>(std::clamp(std::lround(value), 0L, 255L));
    }
  }
  return image;
}

TexturedRoomRenderer::Hit TexturedRoomRenderer::CastRay(const Eigen::Vector3d& o_W,
                                                        const Eigen::Vector3d& d_W) const {
  const double inv[3] = {SafeInverse(d_W.x()), SafeInverse(d_W.y()), SafeInverse(d_W.z())};
  std::vector<double> boxes;
  for (const TexturedBox& box : room_.boxes) {
    boxes.insert(boxes.end(), box.min_W.data(), box.min_W.data() + 3);
    boxes.insert(boxes.end(), box.max_W.data(), box.max_W.data() + 3);
  }
  Hit hit;
  NearestTexturedFace(o_W.data(), d_W.data(), inv, room_.min_W.data(), room_.max_W.data(),
                      boxes.data(), static_cast<int>(room_.boxes.size()), &hit.t_m, &hit.face);
  if (!(hit.t_m > 0.0)) hit.face = -1;
  return hit;
}

}  // namespace mavloc
