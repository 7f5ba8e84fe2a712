#include "frontends/apriltag/detect_tags.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/errors.h"
#include "core/progress.h"
#include "frontends/apriltag/aprilgrid_family.h"
#include "frontends/image_io.h"

#include <opencv2/imgproc.hpp>

namespace mavloc {

namespace {

std::string Num(double value) { return fmt::format("{:.6f}", value); }

bool IsImageFile(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".pgm" || ext == ".bmp";
}

}  // namespace

RectifiedTagDetector::RectifiedTagDetector(const TagDetectorOptions& options,
                                           const CameraModel& camera)
    : detector_(options), camera_(camera) {
  // Aprilgrid corners are X-junctions refined on the raw image (aprilgrid_detector.h): distortion
  // does not bias them, and a remap would only blur them.
  rectify_ = !IsAprilgridFamily(options.family) &&
             camera.distortion_model() != DistortionModel::kNone &&
             std::any_of(camera.distortion().begin(), camera.distortion().end(),
                         [](double k) { return k != 0.0; });
  if (!rectify_) return;
  // The canvas: the bounding box of the raw image's border, undistorted (at most twice the size).
  Eigen::Vector2d lo(0.0, 0.0), hi(0.0, 0.0);
  auto extend = [&](double u, double v) {
    const auto xy = camera.PixelToNormalized(Eigen::Vector2d(u, v));
    if (!xy) return;
    lo = lo.cwiseMin(*xy);
    hi = hi.cwiseMax(*xy);
  };
  const int W = camera.width(), H = camera.height();
  for (int u = 0; u < W; u += 2) {
    extend(u, -0.5);
    extend(u, H - 0.5);
  }
  for (int v = 0; v < H; v += 2) {
    extend(-0.5, v);
    extend(W - 0.5, v);
  }
  const int canvas_w =
      std::min(2 * W, static_cast<int>(std::ceil((hi.x() - lo.x()) * camera.fu())) + 2);
  const int canvas_h =
      std::min(2 * H, static_cast<int>(std::ceil((hi.y() - lo.y()) * camera.fv())) + 2);
  rectified_center_ = Eigen::Vector2d(-lo.x() * camera.fu(), -lo.y() * camera.fv());
  map_x_ = cv::Mat(canvas_h, canvas_w, CV_32F);
  map_y_ = cv::Mat(canvas_h, canvas_w, CV_32F);
  for (int v = 0; v < canvas_h; ++v) {
    for (int u = 0; u < canvas_w; ++u) {
      const Eigen::Vector2d xy((u - rectified_center_.x()) / camera.fu(),
                               (v - rectified_center_.y()) / camera.fv());
      const Eigen::Vector2d uv = camera.NormalizedToPixel(xy);
      map_x_.at<float>(v, u) = static_cast<float>(uv.x());
      map_y_.at<float>(v, u) = static_cast<float>(uv.y());
    }
  }
}

std::vector<TagDetection> RectifiedTagDetector::Detect(const cv::Mat& raw_gray) {
  if (!rectify_ || raw_gray.cols != camera_.width() || raw_gray.rows != camera_.height())
    return detector_.Detect(raw_gray);
  cv::Mat rectified;
  cv::remap(raw_gray, rectified, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(128));
  std::vector<TagDetection> out;
  const double border = detector_.options().min_border_px;
  for (TagDetection det : detector_.Detect(rectified)) {
    bool inside = true;
    auto to_raw = [&](const Eigen::Vector2d& uv_rect) {
      const Eigen::Vector2d xy((uv_rect.x() - rectified_center_.x()) / camera_.fu(),
                               (uv_rect.y() - rectified_center_.y()) / camera_.fv());
      const Eigen::Vector2d uv = camera_.NormalizedToPixel(xy);
      inside = inside && camera_.IsInside(uv, border);
      return uv;
    };
    for (auto& corner : det.corners_px) corner = to_raw(corner);
    det.center_px = to_raw(det.center_px);
    if (inside) out.push_back(det);
  }
  return out;
}

DatasetTagDetections DetectTagsInDataset(const Dataset& dataset, const std::string& camera_name,
                                         const TagDetectorOptions& options, bool rectify) {
  const CameraSensor* camera = dataset.Camera(camera_name);
  if (camera == nullptr)
    throw InputError(dataset.root, 0, "", "the dataset has no camera " + camera_name);
  // The dataset's camera k writes tags<k> (TagObservation::camera).
  const int camera_index = static_cast<int>(camera - dataset.cameras.data());
  CameraModel model = camera->model;
  if (!rectify) model = CameraModel(model.width(), model.height(), model.intrinsics());
  // Without rectification the detector runs on the raw image (a distortion-free model disables it).
  RectifiedTagDetector detector(options, model);
  DatasetTagDetections out;
  for (size_t i = 0; i < camera->frames.size(); ++i) {
    const CameraFrame& frame = camera->frames[i];
    if (frame.image_path.empty() || !std::filesystem::exists(frame.image_path)) {
      out.missing_images.push_back(frame.image_path);
      continue;
    }
    const cv::Mat image = LoadGrayImage(frame.image_path);
    ++out.frames;
    for (const TagDetection& det : detector.Detect(image)) {
      TagObservation obs;
      obs.t_ns = frame.t_ns;
      obs.tag_id = det.id;
      obs.camera = camera_index;
      obs.corners_px = det.corners_px;
      out.observations.push_back(obs);
      const auto tag = dataset.map.tags.find(det.id);
      if (tag == dataset.map.tags.end()) {
        ++out.tags_not_in_map;
        continue;
      }
      out.poses.push_back(
          {frame.t_ns, det.id, EstimateTagPose(det.corners_px, tag->second.size_m, camera->model)});
    }
    if (i % 100 == 0)
      ReportProgress("detect-tags", fmt::format("frame {}/{}", i + 1, camera->frames.size()));
  }
  return out;
}

std::vector<PhotoDetection> DetectTagsInFolder(const std::string& path, TagDetector& detector) {
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_regular_file(path) && IsImageFile(path)) {
    files.push_back(path);
  } else if (std::filesystem::is_directory(path)) {
    for (const auto& entry : std::filesystem::directory_iterator(path)) {
      if (entry.is_regular_file() && IsImageFile(entry.path())) files.push_back(entry.path());
    }
  } else {
    throw InputError(path, 0, "", "neither a folder of images nor an image file");
  }
  std::sort(files.begin(), files.end());
  std::vector<PhotoDetection> out;
  for (const auto& file : files) {
    for (const TagDetection& det : detector.Detect(LoadGrayImage(file.string())))
      out.push_back({file.filename().string(), det});
  }
  return out;
}

std::string TagPosesCsv(const std::vector<TagPoseRow>& poses) {
  std::string csv =
      "#timestamp [ns],tag_id,p_C_T_x [m],p_C_T_y [m],p_C_T_z [m],q_C_T_w [],q_C_T_x [],"
      "q_C_T_y [],q_C_T_z [],rms_reprojection [px]\n";
  for (const auto& row : poses) {
    if (!row.pose.ok) continue;
    const auto& p = row.pose.T_C_T.p;
    const auto& q = row.pose.T_C_T.q;
    csv += fmt::format("{},{},{},{},{},{:.9f},{:.9f},{:.9f},{:.9f},{}\n", row.t_ns, row.tag_id,
                       Num(p.x()), Num(p.y()), Num(p.z()), q.w(), q.x(), q.y(), q.z(),
                       Num(row.pose.rms_reprojection_px));
  }
  return csv;
}

std::string PhotoDetectionsCsv(const std::vector<PhotoDetection>& detections) {
  std::string csv =
      "#file,tag_id,u0 [px],v0 [px],u1 [px],v1 [px],u2 [px],v2 [px],u3 [px],v3 [px]\n";
  for (const auto& d : detections) {
    csv += fmt::format("{},{}", d.file_name, d.detection.id);
    for (const auto& c : d.detection.corners_px)
      csv += fmt::format(",{},{}", Num(c.x()), Num(c.y()));
    csv += "\n";
  }
  return csv;
}

}  // namespace mavloc
