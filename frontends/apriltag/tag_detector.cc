#include "frontends/apriltag/tag_detector.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagStandard41h12.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>

#include "core/errors.h"
#include "frontends/apriltag/aprilgrid_family.h"

namespace mavloc {

// Outside the anonymous namespace because TagDetector::Impl holds one.
struct TagFamilyFunctions {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

namespace {

constexpr TagFamilyFunctions kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {kAprilgridFamilyName, AprilgridFamilyCreate, AprilgridFamilyDestroy},
    {kAprilgridFamilyAlias, AprilgridFamilyCreate, AprilgridFamilyDestroy},
};

const TagFamilyFunctions* FindFamily(const std::string& name) {
  for (const auto& family : kFamilies) {
    if (name == family.name) return &family;
  }
  return nullptr;
}

}  // namespace

std::vector<std::string> SupportedTagFamilies() {
  std::vector<std::string> names;
  for (const auto& family : kFamilies) names.emplace_back(family.name);
  return names;
}

struct TagDetector::Impl {
  const TagFamilyFunctions* functions = nullptr;
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
  ~Impl() {
    if (detector != nullptr) apriltag_detector_destroy(detector);
    if (family != nullptr) functions->destroy(family);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  impl_->functions = FindFamily(options.family);
  if (impl_->functions == nullptr) {
    std::string known;
    for (const auto& name : SupportedTagFamilies()) known += (known.empty() ? "" : ", ") + name;
    throw InputError("", 0, "family",
                     "unknown tag family '" + options.family + "' (known: " + known + ")");
  }
  if (!(options.decimate >= 1.0)) throw InputError("", 0, "decimate", "must be >= 1");
  if (options.threads < 1) throw InputError("", 0, "threads", "must be >= 1");
  if (!(options.sigma >= 0.0)) throw InputError("", 0, "sigma", "must be >= 0");
  if (options.bits_corrected < 0 || options.bits_corrected > 3)
    throw InputError("", 0, "bits_corrected", "must be in [0, 3]");
  impl_->family = impl_->functions->create();
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(impl_->detector, impl_->family, options.bits_corrected);
  impl_->detector->quad_decimate = static_cast<float>(options.decimate);
  impl_->detector->quad_sigma = static_cast<float>(options.sigma);
  impl_->detector->nthreads = options.threads;
  impl_->detector->refine_edges = options.refine_edges;
  impl_->detector->decode_sharpening = options.decode_sharpening;
}

TagDetector::~TagDetector() = default;

bool TagDetector::RefineAprilgrid(const cv::Mat& image, bool separated,
                                  TagDetection* detection) const {
  const AprilgridDetectOptions& grid = options_.aprilgrid;
  // The aprilgrid steps work in mavloc's pixel convention; raw output is shifted back at the end.
  const double to_mavloc = options_.raw_output ? kMavlocFromApriltagPixelShift : 0.0;
  std::array<Eigen::Vector2d, 4> corners;
  for (int k = 0; k < 4; ++k)
    corners[k] = detection->corners_px[k] + Eigen::Vector2d::Constant(to_mavloc);
  if (separated) corners = UndoJunctionSeparation(corners);
  if (grid.refine_corners && !RefineAprilgridCorners(image, grid, &corners)) return false;
  for (int k = 0; k < 4; ++k)
    detection->corners_px[k] = corners[k] - Eigen::Vector2d::Constant(to_mavloc);
  // The centre (the image of the tag centre under the homography) is where the diagonals cross.
  const Eigen::Vector3d d02 = corners[0].homogeneous().cross(corners[2].homogeneous());
  const Eigen::Vector3d d13 = corners[1].homogeneous().cross(corners[3].homogeneous());
  const Eigen::Vector3d centre = d02.cross(d13);
  if (std::abs(centre.z()) > 1e-12)
    detection->center_px = centre.hnormalized() - Eigen::Vector2d::Constant(to_mavloc);
  return true;
}

bool TagDetector::NearBorder(const TagDetection& detection, const cv::Size& size) const {
  const double m = options_.min_border_px;
  if (!(m > 0.0)) return false;
  for (const auto& c : detection.corners_px) {
    if (c.x() < m - 0.5 || c.y() < m - 0.5 || c.x() > size.width - 0.5 - m ||
        c.y() > size.height - 0.5 - m)
      return true;
  }
  return false;
}

std::vector<TagDetection> TagDetector::DetectPass(const cv::Mat& segmented, bool separated,
                                                  const cv::Mat& gray, cv::Mat* refinement_image) {
  std::vector<TagDetection> detections;
  const bool aprilgrid = IsAprilgridFamily(options_.family);
  const AprilgridDetectOptions& grid = options_.aprilgrid;
  // libapriltag reads the image through this plain struct; it does not take ownership.
  image_u8_t header{segmented.cols, segmented.rows, static_cast<int32_t>(segmented.step[0]),
                    const_cast<uint8_t*>(segmented.ptr<uint8_t>())};
  zarray_t* found = apriltag_detector_detect(impl_->detector, &header);
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(found, i, &det);
    TagDetection detection;
    detection.id = det->id;
    detection.hamming = det->hamming;
    detection.decision_margin = det->decision_margin;
    const double shift = options_.raw_output ? 0.0 : kMavlocFromApriltagPixelShift;
    detection.center_px = Eigen::Vector2d(det->c[0] + shift, det->c[1] + shift);
    for (int k = 0; k < 4; ++k) {
      const int source = options_.raw_output ? k : kMavlocCornerFromApriltag[k];
      detection.corners_px[k] =
          Eigen::Vector2d(det->p[source][0] + shift, det->p[source][1] + shift);
    }
    if (aprilgrid && grid.refine_corners && refinement_image->empty())
      *refinement_image = RefinementImage(gray, grid);
    if (aprilgrid && !RefineAprilgrid(*refinement_image, separated, &detection)) continue;
    if (!NearBorder(detection, gray.size())) detections.push_back(detection);
  }
  apriltag_detections_destroy(found);
  return detections;
}

void TagDetector::AddPredictedAprilgridTags(const cv::Mat& gray, const cv::Mat& refinement_image,
                                            std::vector<TagDetection>* detections) const {
  const AprilgridDetectOptions& grid = options_.aprilgrid;
  // The grid steps work in mavloc's pixel convention; raw output is shifted back at the end.
  const double to_mavloc = options_.raw_output ? kMavlocFromApriltagPixelShift : 0.0;
  // Tags found in this round help to predict the others in the next (a gap of several tags fills
  // from its edges).
  constexpr int kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    std::vector<int> ids;
    std::vector<std::array<Eigen::Vector2d, 4>> corners;
    for (const auto& det : *detections) {
      ids.push_back(det.id);
      std::array<Eigen::Vector2d, 4> c = det.corners_px;
      for (auto& p : c) p += Eigen::Vector2d::Constant(to_mavloc);
      corners.push_back(c);
    }
    // The white ring must be inside the image, with the border rule's margin.
    const double border_px = std::max(options_.min_border_px, 1.0);
    const auto predicted =
        PredictMissingAprilgridTags(grid.target, ids, corners, gray.size(), border_px);
    int added = 0;
    for (const auto& tag : predicted) {
      std::array<Eigen::Vector2d, 4> refined = tag.corners_px;
      if (!RefineAprilgridCorners(refinement_image, grid, &refined)) continue;
      double contrast_grey = 0.0;
      const int distance =
          AprilgridCodeDistance(gray, *impl_->family, tag.id, refined, &contrast_grey);
      if (distance < 0 || distance > grid.predicted_max_hamming ||
          !(contrast_grey >= grid.predicted_min_contrast_grey))
        continue;
      TagDetection detection;
      detection.id = tag.id;
      detection.hamming = distance;
      detection.decision_margin = 0.0;  // not decoded by libapriltag
      for (int k = 0; k < 4; ++k)
        detection.corners_px[k] = refined[k] - Eigen::Vector2d::Constant(to_mavloc);
      const Eigen::Vector3d d02 = refined[0].homogeneous().cross(refined[2].homogeneous());
      const Eigen::Vector3d d13 = refined[1].homogeneous().cross(refined[3].homogeneous());
      const Eigen::Vector3d centre = d02.cross(d13);
      if (!(std::abs(centre.z()) > 1e-12)) continue;
      detection.center_px = centre.hnormalized() - Eigen::Vector2d::Constant(to_mavloc);
      if (NearBorder(detection, gray.size())) continue;
      detections->push_back(detection);
      ++added;
    }
    if (added == 0) break;
  }
}

std::vector<TagDetection> TagDetector::Detect(const cv::Mat& gray) {
  std::vector<TagDetection> detections;
  if (gray.empty() || gray.type() != CV_8UC1) return detections;
  const bool aprilgrid = IsAprilgridFamily(options_.family);
  const AprilgridDetectOptions& grid = options_.aprilgrid;
  cv::Mat refinement_image;  // aprilgrid: made on the first detection
  if (!aprilgrid) {
    detections = DetectPass(gray, false, gray, &refinement_image);
  } else {
    detections = DetectPass(grid.separate_junctions ? SeparateDiagonalJunctions(gray) : gray,
                            grid.separate_junctions, gray, &refinement_image);
    std::set<int> ids;
    for (const auto& det : detections) ids.insert(det.id);
    // With the board known, a first pass that found every tag needs no second.
    const bool board_known = grid.target.Validate().empty();
    const bool complete = board_known && static_cast<int>(ids.size()) >= grid.target.NumTags();
    if (grid.separate_junctions && grid.unseparated_pass && !complete) {
      for (const auto& det : DetectPass(gray, false, gray, &refinement_image))
        if (ids.count(det.id) == 0) detections.push_back(det);
    }
    if (grid.refine_corners && board_known && !detections.empty()) {
      if (refinement_image.empty()) refinement_image = RefinementImage(gray, grid);
      AddPredictedAprilgridTags(gray, refinement_image, &detections);
    }
  }
  std::sort(detections.begin(), detections.end(), [](const TagDetection& a, const TagDetection& b) {
    if (a.id != b.id) return a.id < b.id;
    if (a.corners_px[0].x() != b.corners_px[0].x())
      return a.corners_px[0].x() < b.corners_px[0].x();
    return a.corners_px[0].y() < b.corners_px[0].y();
  });
  return detections;
}

}  // namespace mavloc
