#include "solver/estimators/three_point_estimator.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/rotation.h"
#include "solver/estimators/gravity_ekf_estimator.h"
#include "solver/estimators/two_point_estimator.h"
#include "solver/three_point/three_point.h"
#include "solver/three_point/triangle_angle_filter.h"

namespace mavloc {

namespace {}  // namespace

ThreePointEstimator::ThreePointEstimator(const EstimatorOptions& options) : options_(options) {
  // Reject malformed options early.
  GravityEkfOptionsFor(Dataset{}, options_);
  use_true_angles();
  options_.GetDouble("bearing_sigma_deg", 1.0);
  options_.GetInt("min_filter_updates", 1);
  options_.GetDouble("max_correction_deg", 0.0);
  options_.GetDouble("gamma1_deg", 0.0);
  options_.GetDouble("gamma2_deg", 0.0);
}

bool ThreePointEstimator::use_true_angles() const {
  return options_.GetBool("true_angles", false) || options_.Has("gamma1_deg") ||
         options_.Has("gamma2_deg");
}

std::optional<Eigen::Vector2d> ThreePointEstimator::KnownAngles(const Dataset& dataset) const {
  if (options_.Has("gamma1_deg") && options_.Has("gamma2_deg"))
    return Eigen::Vector2d(options_.GetDouble("gamma1_deg", 0.0) * kDeg,
                           options_.GetDouble("gamma2_deg", 0.0) * kDeg);
  const auto& parameters = dataset.map.parameters;
  if (parameters.count("gamma1_rad") && parameters.count("gamma2_rad"))
    return Eigen::Vector2d(parameters.at("gamma1_rad"), parameters.at("gamma2_rad"));
  const auto& landmarks = dataset.map.landmarks_W;
  if (landmarks.count(1) && landmarks.count(2) && landmarks.count(3)) {
    // Signed headings relative to P1 -> P2 (constraint (5)).
    const Eigen::Vector3d d12 = landmarks.at(2) - landmarks.at(1);
    const Eigen::Vector3d d13 = landmarks.at(3) - landmarks.at(1);
    const Eigen::Vector3d d23 = landmarks.at(3) - landmarks.at(2);
    const double a12 = std::atan2(d12.y(), d12.x());
    return Eigen::Vector2d(
        std::remainder(std::atan2(d13.y(), d13.x()) - a12, 2 * std::numbers::pi),
        std::remainder(std::atan2(d23.y(), d23.x()) - a12, 2 * std::numbers::pi));
  }
  return std::nullopt;
}

Applicability ThreePointEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.imu.samples.size() < 2) return Applicability::No("needs imu0 samples");
  if (dataset.Camera("cam0") == nullptr) return Applicability::No("needs cam0 (its T_B_C)");
  bool has[3] = {false, false, false};
  for (const auto& f : dataset.features)
    if (f.landmark_id >= 1 && f.landmark_id <= 3) has[f.landmark_id - 1] = true;
  if (!has[0] || !has[1] || !has[2])
    return Applicability::No("needs features0 of landmarks 1, 2 and 3 (P1, P2, P3)");
  if (const auto why = GroundFeaturesViolation(dataset, 3)) return Applicability::No(*why);
  const auto D = PairDistance(dataset, options_);
  if (!D || !(*D > 0.0))
    return Applicability::No("needs D (option D, map parameter D or landmarks 1, 2)");
  if (use_true_angles() && !KnownAngles(dataset))
    return Applicability::No(
        "true_angles needs gamma1_deg and gamma2_deg, map parameters gamma1_rad and gamma2_rad, "
        "or landmarks 1, 2, 3");
  return Applicability::Yes();
}

Estimate ThreePointEstimator::Run(const Dataset& dataset) {
  const std::optional<Eigen::Vector2d> known =
      use_true_angles() ? KnownAngles(dataset) : std::nullopt;
  Estimate estimate;
  std::vector<std::string> names = PoseQuantityNames(/*with_velocity=*/false);
  if (!known) names.insert(names.end(), {"gamma1", "gamma2"});
  estimate.quantities = MakeQuantityTable(names);

  const auto roll_pitch =
      EstimateRollPitch(dataset.imu.samples, GravityEkfOptionsFor(dataset, options_));
  const CameraSensor* cam = dataset.Camera("cam0");
  const double D = PairDistance(dataset, options_).value_or(0.0);
  const Pose T_W_P = PairFrameInWorld(dataset);
  const double bearing_sigma_rad = options_.GetDouble("bearing_sigma_deg", 1.0) * kDeg;
  const int min_filter_updates = options_.GetInt("min_filter_updates", 1);
  ThreePointOptions solver_options;
  if (options_.Has("max_correction_deg"))
    solver_options.max_correction_rad = options_.GetDouble("max_correction_deg", 0.0) * kDeg;
  TriangleAngleFilter filter;

  for (const FeatureFrame& frame : GroupFeatureFrames(dataset.features)) {
    if (!frame.xy.count(1) || !frame.xy.count(2) || !frame.xy.count(3)) {
      estimate.CountFailure("P1, P2 or P3 not seen");
      continue;
    }
    const RollPitchEstimate* rp = RollPitchAt(roll_pitch, frame.t_ns);
    if (rp == nullptr) {
      estimate.CountFailure("no IMU roll/pitch at the frame time");
      continue;
    }
    ThreePointInput input;
    input.roll_rad = rp->roll_rad;
    input.pitch_rad = rp->pitch_rad;
    input.xy = {frame.xy.at(1), frame.xy.at(2), frame.xy.at(3)};
    input.T_B_C = cam->T_B_C;
    input.distance_m = D;
    if (known) {
      input.gamma1_rad = known->x();
      input.gamma2_rad = known->y();
    } else {
      TriangleAngleInput measurement_input;
      measurement_input.roll_rad = rp->roll_rad;
      measurement_input.pitch_rad = rp->pitch_rad;
      measurement_input.roll_pitch_covariance_rad2 = rp->covariance_rad2;
      measurement_input.xy = input.xy;
      measurement_input.R_B_C = cam->T_B_C.R();
      measurement_input.bearing_sigma_rad = bearing_sigma_rad;
      TriangleAngleMeasurement measurement;
      if (MeasureTriangleAngles(measurement_input, &measurement)) filter.Update(measurement);
      if (!filter.has_estimate() || filter.num_updates() < min_filter_updates) {
        estimate.CountFailure("triangle angles not yet estimated");
        continue;
      }
      input.gamma1_rad = filter.gamma_rad().x();
      input.gamma2_rad = filter.gamma_rad().y();
    }
    ThreePointSolution solution;
    const ThreePointResult result = SolveThreePoint(input, &solution, solver_options);
    if (!result.ok()) {
      estimate.CountFailure(result.reason());
      continue;
    }
    const Pose T_W_B = T_W_P * solution.pose.T_W_B;
    std::vector<double> row = PoseQuantityValues(T_W_B);
    if (!known) row.insert(row.end(), {input.gamma1_rad, input.gamma2_rad});
    estimate.quantities.Append(frame.t_ns, row);
    estimate.poses.push_back({frame.t_ns, T_W_B});
  }
  return estimate;
}

}  // namespace mavloc
