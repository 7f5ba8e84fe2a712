// A room painted with real photographs, rendered by ray casting for natural-feature tracking
// (the euroc-vision scenario flies EuRoC V1_01_easy's real motion through it).
//
// Geometry: the inside of an axis-aligned box (floor, ceiling, four walls) and axis-aligned boxes
// standing in it. Every surface is a rectangle of one photograph (grey), tiled at a fixed metric
// scale (texel_m metres per texel) with mirrored repetition, so that a seam continues the picture
// instead of making an edge, and a photo of any size fills a wall.
//
// Texture coordinates: a face with normal n (pointing at whoever sees it: into the room for the
// room's faces, out of a box for its faces) has the axes e_u = z_W x n (vertical faces) or
// e_u = x_W (floor, ceiling, box tops) and e_v = e_u x n, so that a photo appears upright and
// unmirrored on a wall to a camera in front of it. The face's origin is its corner of smallest
// (e_u, e_v) coordinates; the point W = origin + texel_m (x e_u + y e_v) carries the texture's
// continuous coordinate (x, y), where texel (i, j) covers [i, i+1) x [j, j+1) (centre at
// i + 0.5): TexelToWorld.
//
// Sampling: each pixel casts one ray through its centre (pixel (u, v) has its centre at (u, v)),
// the unit ray of every pixel precomputed once through the camera model's undistortion. The
// texture is sampled trilinearly from a mip pyramid (2x2 box averages), the level chosen from the
// pixel's footprint on the surface (range x the pixel's angular size / cos(incidence), cos clamped
// at 0.25): no aliasing at range, full detail up close. Shading is a constant brightness per face
// (a distant light, Lambert's cosine plus ambient), the same from every viewpoint (brightness
// constancy, as a tracker assumes). Pixels whose ray cannot be undistorted are black.
//
// Motion blur: Render averages the images of several poses over the exposure (the caller picks
// them along the motion). The 8-bit image adds Gaussian noise drawn from a seed: the same poses and
// seed give the same bytes.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/pose.h"

namespace mavloc {

struct TexturedBox {
  Eigen::Vector3d min_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_W = Eigen::Vector3d::Ones();
};

struct TexturedRoom {
  Eigen::Vector3d min_W = Eigen::Vector3d(-4.0, -4.0, 0.0);  // the room's inside
  Eigen::Vector3d max_W = Eigen::Vector3d(4.0, 4.0, 4.0);
  std::vector<TexturedBox> boxes;  // inside the room, not overlapping
  double texel_m = 0.004;          // metres per texel on every surface
};

// One photograph: grey levels 0..255 (CV_32F), level 0 cropped to a multiple of 2^(levels - 1)
// so that every level halves the one below exactly.
struct RoomTexture {
  std::string path;
  std::vector<cv::Mat> levels;
};

struct RoomTextures {
  std::vector<RoomTexture> textures;  // in file-name order
  std::vector<std::string> skipped;   // "path: reason" of each file that could not be used
};

// Every PNG and JPEG file (.png, .jpg, .jpeg in any case) of `folder`, in name order, as grey
// textures. A file that cannot be read or decoded, or is smaller than 32 x 32, is skipped and
// listed in `skipped`. Throws InputError naming the folder and `setting` when the folder does not
// exist or holds no usable image.
RoomTextures LoadRoomTextures(const std::string& folder, const std::string& setting);
// The same from images already in memory (8-bit grey or BGR), named by `names`.
RoomTextures RoomTexturesFromImages(const std::vector<cv::Mat>& images,
                                    const std::vector<std::string>& names);

// A planar face of the room or of a box, with its texture frame (see the top of the file).
struct TexturedFace {
  int normal_axis = 0;    // the face lies in the plane x_W[normal_axis] = plane
  double plane = 0.0;     // [m]
  Eigen::Vector3d n_W;    // unit normal, towards the side the face is seen from
  Eigen::Vector3d e_u_W;  // texture x axis
  Eigen::Vector3d e_v_W;  // texture y axis
  Eigen::Vector3d origin_W;
  int texture = 0;          // index into RoomTextures::textures
  double brightness = 1.0;  // shading factor
  int box = -1;             // -1: the room; else the index of the box
};

// The faces in the renderer's order: room faces 2a (x_W[a] = min) and 2a + 1 (max), then for box
// b its faces 6 + 6b + 2a (min side) and 6 + 6b + 2a + 1 (max side). Face k is painted with
// texture k mod texture_count, except that the room's floor (face 4) and ceiling (5) take the
// textures whose file names start with "aero" when there are such (aerial photographs look like a
// floor from above); a folder without them is used in order.
std::vector<TexturedFace> TexturedRoomFaces(const TexturedRoom& room, const RoomTextures& textures);

// The world point of a face's continuous texture coordinate (x, y) in texels.
Eigen::Vector3d TexelToWorld(const TexturedFace& face, double x_texel, double y_texel,
                             double texel_m);

// The room and its boxes as flat map.yaml parameters (WorldMap::parameters):
//   textured_room_min_x/y/z, textured_room_max_x/y/z, textured_room_texel_m [m],
//   textured_box_count, textured_box_<i>_min_x/y/z, textured_box_<i>_max_x/y/z [m].
void TexturedRoomToMapParameters(const TexturedRoom& room,
                                 std::map<std::string, double>* parameters);

struct TexturedRenderOptions {
  double gain = 1.0;              // multiplies the photographs' grey levels (exposure x gain)
  double noise_sigma_grey = 2.0;  // Gaussian sensor noise, grey levels
};

class TexturedRoomRenderer {
 public:
  TexturedRoomRenderer(const CameraModel& camera, const TexturedRoom& room,
                       std::shared_ptr<const RoomTextures> textures,
                       const TexturedRenderOptions& options = {});

  // The noise-free image (CV_32F, grey levels) averaged over the camera poses T_W_C (one pose:
  // no blur), gain applied, not clamped.
  cv::Mat RenderIdeal(const std::vector<Pose>& T_W_C) const;
  // The 8-bit image: RenderIdeal plus noise drawn from noise_seed, rounded and clamped to 0..255.
  cv::Mat Render(const std::vector<Pose>& T_W_C, uint64_t noise_seed) const;

  // The nearest hit along a ray from o_W in direction d_W (unit): the distance and the face index
  // (TexturedRoomFaces' order), or face -1 when the ray leaves through nothing (o_W outside).
  struct Hit {
    double t_m = 0.0;
    int face = -1;
  };
  Hit CastRay(const Eigen::Vector3d& o_W, const Eigen::Vector3d& d_W) const;

  const CameraModel& camera() const { return camera_; }
  const std::vector<TexturedFace>& faces() const { return faces_; }
  // Pixels whose ray could not be undistorted (rendered black).
  int invalid_pixels() const { return invalid_pixels_; }

 private:
  struct Level;
  void PrecomputeRays();
  void RenderRows(const Pose& T_W_C, int row_begin, int row_end, float weight,
                  cv::Mat* accumulator) const;
  float Shade(int face, const float* p_W, float footprint_m) const;
  static float SampleLevel(const Level& level, float x, float y);

  CameraModel camera_;
  TexturedRoom room_;
  std::shared_ptr<const RoomTextures> textures_;
  TexturedRenderOptions options_;
  std::vector<TexturedFace> faces_;
  // Per face, in float for the inner loop: origin, e_u, e_v divided by texel_m, brightness x gain.
  struct FaceLookup {
    float origin[3];
    float u_per_m[3];
    float v_per_m[3];
    float gain;
    int texture;
  };
  std::vector<FaceLookup> lookups_;
  // Per texture level, the mirrored index of every column and row of a period of 2 sizes (+1).
  struct Level {
    const float* pixels = nullptr;
    int width = 0, height = 0;
    size_t stride = 0;                               // floats per row
    float inv_period_x = 0.0f, inv_period_y = 0.0f;  // 1 / (2 x size)
    std::vector<int> mirror_x, mirror_y;
  };
  std::vector<std::vector<Level>> levels_;  // [texture][level]
  std::vector<float> boxes_;                // 6 floats per box: min xyz, max xyz
  float inv_texel_m_ = 0.0f;
  // Per pixel: the unit ray in C (3 floats) and its angular size [rad] (0: invalid ray).
  std::vector<float> rays_C_;
  std::vector<float> pixel_angle_rad_;
  int invalid_pixels_ = 0;
};

}  // namespace mavloc
