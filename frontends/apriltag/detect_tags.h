// Tag detection over a dataset's camera stream or a folder of photos (`mavloc detect-tags`):
// - a dataset: every frame of cam0 through the detector -> tags0 rows (timestamp, tag id, the 4
//   corners in distorted pixels, mavloc order), plus the per-tag pose of each detection whose tag
//   is in the map (tag_pose.h: IPPE_SQUARE on the undistorted corners);
//   (tags1 for cam1: the dataset's camera k writes tags<k>, TagObservation::camera = k);
// - a folder of photos (.jpg, .jpeg, .png, .pgm, .bmp, sorted by name), or one image file: one row
//   per detection with the image file name, the tag id and its 4 corners.
// The CSV texts are returned; the caller writes them (atomically).
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "frontends/apriltag/tag_detector.h"
#include "frontends/apriltag/tag_pose.h"

namespace mavloc {

// Detection through an ideal pinhole view. libapriltag fits straight lines to the tag edges, but a
// lens with distortion bends them (radial-tangential k1 = -0.28 for the EuRoC-like arena camera):
// fitted on the raw image, corners are off by up to ~0.8 px near the image edges. This detector
// first rectifies the image to a distortion-free pinhole camera with the same focal lengths, on a
// canvas large enough to hold every raw pixel (barrel distortion pushes the periphery outwards;
// about 1.2 x 1.2 times the raw size for the arena camera), by cv::remap (bilinear: rectified
// pixel -> normalized -> distorted pixel); it detects there and maps the corners back to distorted
// pixels of the raw image through the camera model, so they stay in the tags0 convention. With no
// distortion, and for the aprilgrid families (whose corners are X-junctions measured on the raw
// image, aprilgrid_detector.h), it is the plain detector.
class RectifiedTagDetector {
 public:
  RectifiedTagDetector(const TagDetectorOptions& options, const CameraModel& camera);
  // Corners in raw (distorted) pixels, mavloc order; same border rule as TagDetector, on the raw
  // image.
  std::vector<TagDetection> Detect(const cv::Mat& raw_gray);
  const TagDetectorOptions& options() const { return detector_.options(); }

 private:
  TagDetector detector_;
  CameraModel camera_;
  bool rectify_ = false;
  Eigen::Vector2d rectified_center_ = Eigen::Vector2d::Zero();  // principal point on the canvas
  cv::Mat map_x_, map_y_;
};

struct TagPoseRow {
  TimeNs t_ns = 0;
  int tag_id = 0;
  TagPoseResult pose;
};

struct DatasetTagDetections {
  std::vector<TagObservation> observations;  // tags0, time-ordered
  std::vector<TagPoseRow> poses;             // per-tag poses of the observations in the map
  int frames = 0;                            // frames processed
  std::vector<std::string> missing_images;   // frames listed but absent on disk (skipped)
  int tags_not_in_map = 0;
};

// Throws InputError when the camera is absent or an image cannot be decoded. With rectify, images
// go through RectifiedTagDetector (the default of `mavloc detect-tags`).
DatasetTagDetections DetectTagsInDataset(const Dataset& dataset, const std::string& camera_name,
                                         const TagDetectorOptions& options, bool rectify = true);

struct PhotoDetection {
  std::string file_name;
  TagDetection detection;
};

// `path` is a folder of images or a single image file. Throws InputError for a missing path or an
// image that cannot be decoded.
std::vector<PhotoDetection> DetectTagsInFolder(const std::string& path, TagDetector& detector);

// "#timestamp [ns],tag_id,p_C_T_x [m],...,q_C_T_w,x,y,z,rms_reprojection [px]".
std::string TagPosesCsv(const std::vector<TagPoseRow>& poses);
// "#file,tag_id,u0 [px],v0 [px],...,v3 [px]".
std::string PhotoDetectionsCsv(const std::vector<PhotoDetection>& detections);

}  // namespace mavloc
