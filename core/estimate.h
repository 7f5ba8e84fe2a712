// What an estimator returns: named quantities over time, full poses when it estimates them, and
// optional covariances (for NEES), plus a count of frames where it gave no solution and why.
#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "core/quantities.h"

namespace mavloc {

struct StampedCovariance {
  TimeNs t_ns = 0;
  Eigen::MatrixXd covariance;  // over Estimate::covariance_names, same units as the quantities
};

// A constant the estimator estimated (calibration, board tilt, statistics of its solution), with
// its standard deviation when known. Units are SI (radians inside; reports convert).
struct EstimatedParameter {
  double value = 0.0;
  std::optional<double> sigma;
  std::string unit;  // "m", "rad", "s", "px", "" (counts)
};

// An estimated camera-IMU extrinsic T_B_C with its marginal covariance over
// [p_B_C (m); dtheta (rad, right perturbation R_B_C Exp(dtheta))].
struct EstimatedExtrinsic {
  Pose T_B_C;
  std::optional<Eigen::Matrix<double, 6, 6>> covariance;
};

struct Estimate {
  QuantityTable quantities;
  std::vector<StampedPose> poses;  // T_W_B when the estimator gives a full 6-DoF pose
  // Board maps (MapFrame::kBoard): the estimator's map-to-world transform T_W_M in the convention
  // of core/board_frame.h (its gravity estimate), so that map points can be reprojected.
  std::optional<Pose> T_W_M;
  // Estimated constants by name ("time_offset", "board_roll", "reprojection_rms", ...).
  std::map<std::string, EstimatedParameter> parameters;
  // Estimated camera extrinsics by camera name ("cam0", "cam1").
  std::map<std::string, EstimatedExtrinsic> extrinsics;
  std::vector<std::string> covariance_names;
  std::vector<StampedCovariance> covariances;
  // Frames (or epochs) without a solution, counted by reason ("features coincident", ...).
  std::map<std::string, int> failures;
  // Measurements the estimator left out while the frame still got a pose (a tag gated out by a
  // filter, a frame whose attitude disagrees with the IMU), counted by reason.
  std::map<std::string, int> rejections;
  // Events a reader of the report should see, one line each, with their time (a filter reset
  // after lost lock, ...).
  std::vector<std::string> events;

  void CountFailure(const std::string& reason) { ++failures[reason]; }
  void CountRejection(const std::string& reason, int count = 1) { rejections[reason] += count; }
  int FailureCount() const;
  int RejectionCount() const;
};

}  // namespace mavloc
