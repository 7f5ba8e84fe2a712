// The natural-feature frontend of one frame after the other (DESIGN.md "Frontends"): corners
// detected in a grid (grid_detector.h), tracked frame to frame by pyramidal Lucas-Kanade (Bouguet's
// pyramidal implementation in OpenCV) started where the gyro rotation since the previous frame
// puts them (gyro_rotation.h: a far point moves by the rotation alone, so only the parallax is left
// to the search), kept only when tracking back from the new frame lands within
// forward_backward_px of where the track was (Kalal et al., ICPR 2010), undistorted through the
// camera model (radtan or equidistant), and checked by RANSAC over the frame pair: the 2-point
// RANSAC over the translation direction with the gyro's rotation (two_point_ransac.h, Troiani et
// al., ICRA 2014), or OpenCV's 5-point essential matrix (five_point_ransac.h) when no rotation is
// known or the option asks for it. With a second camera every track of cam0 is matched into cam1
// (Lucas-Kanade from the rotation-only prediction, forward-backward check, epipolar check with
// E = [t_C1_C0]x R_C1_C0 of the extrinsics, positive depth); a match gives the track's cam1
// observation with the same id.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "frontends/features/grid_detector.h"

namespace mavloc {

enum class FrameOutlierRejection { kTwoPoint, kFivePoint, kNone };

struct FeatureTrackerOptions {
  GridDetectorOptions detector;
  int klt_window_px = 21;
  int klt_pyramid_levels = 3;
  int klt_max_iterations = 30;
  double klt_epsilon_px = 0.01;
  double forward_backward_px = 1.0;
  bool use_gyro = true;  // predict with the gyro rotation and give it to the 2-point RANSAC
  FrameOutlierRejection rejection = FrameOutlierRejection::kTwoPoint;
  double ransac_threshold_px = 1.5;  // epipolar error at cam0's focal length
  double ransac_confidence = 0.999;
  int ransac_max_iterations = 500;
  double stereo_epipolar_px = 2.0;  // at cam1's focal length
  int stereo_pyramid_levels = 4;
  double stereo_min_depth_m = 0.1;
  uint64_t seed = 1;  // RANSAC sampling
};

// Empty when usable; otherwise which option is out of range and why.
std::string ValidateFeatureTrackerOptions(const FeatureTrackerOptions& options);

// What happened to the tracks in one frame (cam0, and the cam1 matches).
struct FeatureFrameStatistics {
  TimeNs t_ns = 0;
  int tracked = 0;     // tracks continued into this frame past every test
  int new_tracks = 0;  // corners detected in this frame
  int lost = 0;        // Lucas-Kanade failed or the track left the image
  int rejected_forward_backward = 0;
  int rejected_ransac = 0;
  int stereo_matched = 0;
  int stereo_rejected = 0;  // failed, forward-backward or behind a camera
  int stereo_rejected_epipolar = 0;
  bool cam1_used = false;
  double mean_track_length = 0.0;  // frames, over the tracks of this frame
  double time_ms = 0.0;            // this frame's tracking (both cameras), not the image loading
};

struct FeatureFrameOutput {
  std::vector<FeatureObservation> cam0;  // camera = 0
  std::vector<FeatureObservation> cam1;  // camera = 1, same ids as their cam0 tracks
  FeatureFrameStatistics statistics;
  std::vector<int> ended_track_lengths;  // tracks lost in this frame: their lengths in frames
};

class FeatureTracker {
 public:
  // cam1 may be null (mono). The cameras' models and T_B_C are copied.
  FeatureTracker(const CameraSensor& cam0, const CameraSensor* cam1,
                 const FeatureTrackerOptions& options);
  // One frame: gray0 of cam0, gray1 of cam1 (empty: no stereo match in this frame), and the body
  // rotation since the previous frame R_Bprev_Bcurr (nullopt: unknown).
  FeatureFrameOutput Track(TimeNs t_ns, const cv::Mat& gray0, const cv::Mat& gray1,
                           const std::optional<Eigen::Quaterniond>& q_Bprev_Bcurr);
  // The lengths of the tracks still alive (for the statistics at the end of a log).
  std::vector<int> AliveTrackLengths() const;

 private:
  struct TrackState {
    int id = 0;
    cv::Point2f px;
    Eigen::Vector2d xy;  // normalized, undistorted
    int length = 1;      // frames
  };
  void TrackIntoFrame(const std::vector<cv::Mat>& pyramid,
                      const std::optional<Eigen::Quaterniond>& q_Bprev_Bcurr,
                      FeatureFrameOutput* out);
  // Inlier mask of the frame pair's matches (unit bearings in the previous and current cam0).
  std::vector<bool> RejectOutliers(const std::vector<Eigen::Vector3d>& f_prev,
                                   const std::vector<Eigen::Vector3d>& f_curr, bool gyro,
                                   const Eigen::Matrix3d& R_Ccurr_Cprev);
  void AddNewTracks(const cv::Mat& gray0, FeatureFrameOutput* out);
  void MatchIntoCam1(const std::vector<cv::Mat>& pyramid0, const cv::Mat& gray1,
                     FeatureFrameOutput* out);

  CameraModel model0_;
  Pose T_B_C0_;
  std::optional<CameraModel> model1_;
  Pose T_C1_C0_;
  FeatureTrackerOptions options_;
  std::vector<TrackState> tracks_;
  std::vector<cv::Mat> previous_pyramid_;
  int next_id_ = 0;
  unsigned frame_index_ = 0;
};

}  // namespace mavloc
