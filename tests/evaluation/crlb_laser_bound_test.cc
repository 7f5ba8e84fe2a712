// The smoother's Cramér–Rao bound on laser-only data (evaluation/crlb/laser_bound.h,
// smoother_bound.h):
// - the analytic Jacobians against central differences of the simulator's own functions
//   (SimulateLaserSpots with zero noise for the spot's bearing angle, LaserTruthQuantities for
//   d, v_o, roll, pitch, alpha), with the laser-plane camera and with a camera moved and turned in
//   B (T_B_C with a translation, as the model allows);
// - the bound on the five quantities does not depend on where the smoother's (minimal) gauge
//   priors sit: the same with them on the last keyframe, while the position bound changes
//   completely;
// - efficiency: over fixed Monte-Carlo seeds of laser-plane the smoother's RMSE of each quantity
//   is not below the bound beyond Monte-Carlo noise (a bound above an efficient estimator's error
//   would be a bug), and the ratios are printed;
// - datasets outside the model say why.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "core/rotation.h"
#include "datasets/scenarios/laser_plane.h"
#include "evaluation/crlb/laser_bound.h"
#include "evaluation/crlb/laser_efficiency.h"
#include "evaluation/crlb/smoother_bound.h"
#include "solver/estimator.h"
#include "solver/estimators/smoother_estimator.h"

#include "tests/scenario_support.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

using testing::CentralDifferenceJacobian;
using testing::Simulate;

// The model of a laser-plane dataset as the bound builds it (L, noise, the true plane).
LaserSpotModel ModelOf(const Dataset& dataset) {
  const SmootherProblemOptions options =
      SmootherEstimator(EstimatorOptions()).ProblemOptionsFor(dataset);
  std::string why;
  const auto model = LaserSpotModelFor(dataset, options.laser_beam, options.laser_sigma_rad,
                                       dataset.ground_truth.front().T_W_B, &why);
  EXPECT_TRUE(model.has_value()) << why;
  return model.value_or(LaserSpotModel{});
}

// The state perturbed by delta = [dp (3), dtheta (3), dv (3), dbg (3), dba (3), plane (3)].
struct Perturbed {
  Pose T_W_B;
  Eigen::Vector3d v_W;
  Plane plane;
};
Perturbed Perturb(const Pose& T_W_B, const Eigen::Vector3d& v_W, const Plane& plane,
                  const Eigen::VectorXd& delta) {
  Perturbed out;
  out.T_W_B = Pose(T_W_B.q * ExpQuaternion(delta.segment<3>(3)), T_W_B.p + delta.head<3>());
  out.v_W = v_W + delta.segment<3>(6);
  out.plane = PerturbPlane(plane, delta.tail<3>());
  return out;
}

// The simulator's noiseless bearing angle atan(x) of the spot (SimulateLaserSpots).
double SimulatedBearing(const Pose& T_W_B, const Pose& T_B_C, double L_m, const Plane& plane) {
  int missed = 0;
  const std::vector<LaserObservation> spots =
      SimulateLaserSpots([&](TimeNs) { return T_W_B * T_B_C; }, {0}, L_m, plane, 0.0, 1, &missed);
  return spots.empty() ? std::nan("") : std::atan(spots.front().xy.x());
}

// The simulator's truth quantities of one state (LaserTruthQuantities).
Eigen::VectorXd SimulatedQuantities(const Pose& T_W_B, const Eigen::Vector3d& v_W,
                                    const Pose& T_B_C, const Plane& plane) {
  GroundTruthState state;
  state.T_W_B = T_W_B;
  state.v_W = v_W;
  const QuantityTable table = LaserTruthQuantities({state}, T_B_C, plane);
  return Eigen::Map<const Eigen::VectorXd>(table.rows.front().data(), 5);
}

// Differences of quantity vectors with the angles wrapped.
Eigen::VectorXd QuantityMinus(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd d = a - b;
  for (int i = 2; i < 5; ++i) d(i) = WrapAngle(d(i));
  return d;
}

void CheckJacobians(const Dataset& dataset, const Pose& T_B_C, const std::string& label) {
  LaserSpotModel model = ModelOf(dataset);
  model.T_B_C = T_B_C;
  int checked = 0;
  double worst_bearing = 0.0, worst_quantity = 0.0;
  for (size_t i = 0; i < dataset.ground_truth.size(); i += 97) {
    const GroundTruthState& truth = dataset.ground_truth[i];
    Eigen::Matrix<double, 1, 9> J;
    if (!LaserSpotBearingJacobian(model, truth.T_W_B, &J)) continue;
    // The bearing: the simulator's value and its central differences over [dp, dtheta, plane].
    const double value = SimulatedBearing(truth.T_W_B, T_B_C, model.L_m, model.plane);
    ASSERT_NEAR(*LaserSpotBearing(model, truth.T_W_B), value, 1e-12) << label;
    const auto bearing = [&](const Eigen::VectorXd& d9) {
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(18);
      delta.head<6>() = d9.head<6>();
      delta.tail<3>() = d9.tail<3>();
      const Perturbed p = Perturb(truth.T_W_B, truth.v_W, model.plane, delta);
      return Eigen::VectorXd(
          Eigen::VectorXd::Constant(1, SimulatedBearing(p.T_W_B, T_B_C, model.L_m, p.plane)));
    };
    const Eigen::MatrixXd J_numeric = CentralDifferenceJacobian(bearing, Eigen::VectorXd::Zero(9));
    const double bearing_error = (J_numeric - J).norm() / std::max(J.norm(), 1e-12);
    worst_bearing = std::max(worst_bearing, bearing_error);
    EXPECT_LT(bearing_error, 1e-6) << label << " row " << i << "\n" << J << "\n" << J_numeric;

    // The quantities over the 15 error-state components and the plane.
    const Eigen::VectorXd q = SimulatedQuantities(truth.T_W_B, truth.v_W, T_B_C, model.plane);
    const Vector5d q_model = LaserQuantitiesAt(model, truth.T_W_B, truth.v_W);
    ASSERT_LT(QuantityMinus(q, q_model).norm(), 1e-12) << label;
    const auto quantities = [&](const Eigen::VectorXd& delta) {
      const Perturbed p = Perturb(truth.T_W_B, truth.v_W, model.plane, delta);
      return SimulatedQuantities(p.T_W_B, p.v_W, T_B_C, p.plane);
    };
    const Eigen::MatrixXd Q_numeric =
        CentralDifferenceJacobian(quantities, 18, QuantityMinus, 1e-6);
    const Eigen::Matrix<double, 5, 18> Q = LaserQuantityJacobian(model, truth.T_W_B, truth.v_W);
    const double quantity_error = (Q_numeric - Q).norm() / Q.norm();
    worst_quantity = std::max(worst_quantity, quantity_error);
    EXPECT_LT(quantity_error, 1e-6) << label << " row " << i << "\n" << Q << "\n" << Q_numeric;
    ++checked;
  }
  std::printf("%s: %d states, worst relative difference: bearing %.2g, quantities %.2g\n",
              label.c_str(), checked, worst_bearing, worst_quantity);
  EXPECT_GT(checked, 5) << label;
}

TEST(CrlbLaserBound, JacobiansMatchCentralDifferencesOfTheSimulator) {
  const Dataset dataset = Simulate("laser-plane", 1, 6.0);
  ASSERT_FALSE(dataset.ground_truth.empty());
  CheckJacobians(dataset, dataset.cameras.front().T_B_C, "laser-plane camera");
  // A camera moved and turned in B (the simulator's spot follows T_W_B * T_B_C).
  const Pose T_B_C(Eigen::Quaterniond(ExpSO3(Eigen::Vector3d(0.05, -0.08, 0.3))),
                   Eigen::Vector3d(0.04, -0.02, 0.03));
  CheckJacobians(dataset, T_B_C, "moved camera");
}

TEST(CrlbLaserBound, QuantitiesAreTheDatasetsTruthAndTheirBoundIsGaugeInvariant) {
  const Dataset dataset = Simulate("laser-plane", 3, 10.0);
  const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
  ASSERT_TRUE(bound.ok) << bound.reason;
  ASSERT_TRUE(bound.laser_only);
  ASSERT_TRUE(bound.plane_covariance.has_value());
  EXPECT_GT(bound.visual_residuals, 90);
  // The bound's true quantities are the dataset's at the keyframe stamps.
  const QuantityTable& truth = dataset.truth_quantities;
  int matched = 0;
  for (const CrlbKeyframe& kf : bound.keyframes) {
    ASSERT_TRUE(kf.laser.has_value());
    for (size_t r = 0; r < truth.size(); ++r) {
      if (truth.t_ns[r] != kf.t_ns) continue;
      for (int i = 0; i < 5; ++i)
        EXPECT_NEAR(kf.laser->truth(i), truth.rows[r][truth.Index(LaserQuantityNames()[i])], 1e-9);
      ++matched;
    }
  }
  EXPECT_GT(matched, static_cast<int>(bound.keyframes.size()) / 2);

  CrlbModelOptions last;
  last.laser_gauge_keyframe = -1;
  const SmootherCrlb moved = ComputeSmootherCrlb(dataset, EstimatorOptions(), last);
  ASSERT_TRUE(moved.ok) << moved.reason;
  ASSERT_EQ(moved.keyframes.size(), bound.keyframes.size());
  double worst = 0.0;
  for (size_t k = 0; k < bound.keyframes.size(); ++k) {
    const Vector5d a = bound.keyframes[k].laser->SmoothingSigmas();
    const Vector5d b = moved.keyframes[k].laser->SmoothingSigmas();
    for (int i = 0; i < 5; ++i) worst = std::max(worst, std::abs(b(i) / a(i) - 1.0));
  }
  // The first position: fixed by the gauge priors there (1 mm per axis), free with them at the
  // end.
  const double p0_first = std::sqrt(bound.keyframes.front().smoothing.block<3, 3>(0, 0).trace());
  const double p0_last = std::sqrt(moved.keyframes.front().smoothing.block<3, 3>(0, 0).trace());
  std::printf(
      "gauge on the last keyframe: worst relative change of a quantity's sigma %.2g; "
      "first position sigma %.3g m -> %.3g m\n",
      worst, p0_first, p0_last);
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(p0_first, 2e-3);
  EXPECT_GT(p0_last, 1e2 * p0_first);

  // The same with the IMU linearised at the noisy samples (the other datasets' model): the
  // rotations about gravity and about the normal are no longer exact null directions (printed).
  CrlbModelOptions samples;
  samples.laser_true_imu_rates = false;
  samples.laser_gauge_keyframe = -1;
  const SmootherCrlb noisy = ComputeSmootherCrlb(dataset, EstimatorOptions(), samples);
  ASSERT_TRUE(noisy.ok) << noisy.reason;
  double worst_noisy = 0.0;
  for (size_t k = 0; k < bound.keyframes.size(); ++k) {
    const Vector5d a = bound.keyframes[k].laser->SmoothingSigmas();
    const Vector5d b = noisy.keyframes[k].laser->SmoothingSigmas();
    for (int i = 0; i < 5; ++i) worst_noisy = std::max(worst_noisy, std::abs(b(i) / a(i) - 1.0));
  }
  std::printf("linearised at the samples, gauge on the last keyframe: worst relative change %.2g\n",
              worst_noisy);

  // The filtering bound (plane unknown to a causal estimator) is never below the smoothing bound
  // and equals it at the last keyframe, within the numerical precision of the two paths (relative
  // 1e-5 here: the gauge priors are 1e12 beside data information of 1e2 .. 1e6).
  int filtered = 0;
  for (const CrlbKeyframe& kf : bound.keyframes) {
    if (!kf.laser->filtering) continue;
    ++filtered;
    for (int i = 0; i < 5; ++i)
      EXPECT_GE((*kf.laser->filtering)(i, i), kf.laser->smoothing(i, i) * (1.0 - 1e-4)) << i;
  }
  EXPECT_GT(filtered, static_cast<int>(bound.keyframes.size()) / 2);
  // How fast the causal bound falls with no prior on the plane (printed).
  for (const size_t k :
       {size_t{5}, size_t{10}, size_t{20}, size_t{50}, bound.keyframes.size() - 1}) {
    const CrlbLaserQuantities& q = *bound.keyframes.at(k).laser;
    if (!q.filtering) continue;
    std::printf(
        "keyframe %zu: filtering / smoothing sigma d %.3g / %.3g mm, alpha %.3g / %.3g deg\n", k,
        1e3 * std::sqrt((*q.filtering)(0, 0)), 1e3 * std::sqrt(q.smoothing(0, 0)),
        std::sqrt((*q.filtering)(4, 4)) / kDeg, std::sqrt(q.smoothing(4, 4)) / kDeg);
  }
  ASSERT_TRUE(bound.keyframes.back().laser->filtering.has_value());
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(std::sqrt((*bound.keyframes.back().laser->filtering)(i, i)),
                std::sqrt(bound.keyframes.back().laser->smoothing(i, i)),
                1e-4 * std::sqrt(bound.keyframes.back().laser->smoothing(i, i)));
}

// The Monte-Carlo size: the default, or MAVLOC_CRLB_LASER_SEEDS and MAVLOC_CRLB_LASER_DURATION_S
// for a longer measurement (docs/cramer-rao.md: e.g. 40 seeds x 30 s; the paper's run is 60 s).
int SeedCount(int default_count) {
  const char* text = std::getenv("MAVLOC_CRLB_LASER_SEEDS");
  return text ? std::max(2, std::atoi(text)) : default_count;
}
double DurationS(double default_s) {
  const char* text = std::getenv("MAVLOC_CRLB_LASER_DURATION_S");
  return text ? std::max(2.0, std::atof(text)) : default_s;
}

void PrintRatios(const char* title, const LaserEfficiencySums& total) {
  std::printf("%s\n", title);
  for (const std::string& name : LaserQuantityNames()) {
    const double scale = name == "d" || name == "v_o" ? 1e3 : 1.0 / kDeg;
    std::printf("  %-5s bound %.4g, RMSE %.4g (mm, mm/s, deg), ratio %.3f +- %.3f\n", name.c_str(),
                scale * total.BoundRms(name), scale * total.Rmse(name), total.Ratio(name),
                total.RatioStandardError(name));
  }
}

// The smoother against the smoothing bound, squared errors summed over seeds before the ratio;
// laser-ekf (its seed, the paper's filter) against the filtering bound is printed beside it.
TEST(CrlbLaserBound, SmootherIsNotBelowTheBound) {
  const double duration_s = DurationS(20.0);
  const int seeds = SeedCount(6);
  LaserEfficiencySums smoother_total, ekf_total;
  for (int seed = 1; seed <= seeds; ++seed) {
    const Dataset dataset = Simulate("laser-plane", static_cast<uint64_t>(seed), duration_s);
    const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
    ASSERT_TRUE(bound.ok) << bound.reason;
    EstimatorOptions options;
    options.Set("seed.init_seed", std::to_string(seed));  // as `repro smoother` runs it
    SmootherEstimator smoother(options);
    const Estimate estimate = smoother.Run(dataset);
    const LaserEfficiencySums run =
        CompareLaserWithBound(bound, estimate.quantities, BoundKind::kSmoothing);
    EXPECT_EQ(run.runs, 1) << "seed " << seed;
    smoother_total.Add(run);

    const EstimatorEntry* entry = FindEstimator("laser-ekf");
    ASSERT_NE(entry, nullptr);
    EstimatorOptions ekf_options;
    ekf_options.Set("init_seed", std::to_string(seed));
    const Estimate ekf = entry->create(ekf_options)->Run(dataset);
    ekf_total.Add(CompareLaserWithBound(bound, ekf.quantities, BoundKind::kFiltering));
  }
  ASSERT_EQ(smoother_total.runs, seeds);
  const std::string title = "laser-plane, " + std::to_string(seeds) + " seeds x " +
                            std::to_string(static_cast<int>(duration_s)) + " s, ";
  PrintRatios((title + "smoother RMSE / smoothing bound:").c_str(), smoother_total);
  PrintRatios((title + "laser-ekf RMSE / filtering bound:").c_str(), ekf_total);
  for (const std::string& name : LaserQuantityNames()) {
    const double ratio = smoother_total.Ratio(name), se = smoother_total.RatioStandardError(name);
    RecordProperty(name + "_ratio", std::to_string(ratio));
    // Not below the bound beyond 3 Monte-Carlo standard errors.
    EXPECT_GT(ratio, 1.0 - 3.0 * se) << name;
  }
}

TEST(CrlbLaserBound, DataOutsideTheModelSayWhy) {
  Dataset dataset = Simulate("laser-plane", 1, 3.0);
  dataset.map.plane.reset();
  const SmootherCrlb no_plane = ComputeSmootherCrlb(dataset);
  EXPECT_FALSE(no_plane.ok);
  EXPECT_NE(no_plane.reason.find("plane"), std::string::npos) << no_plane.reason;

  Dataset tilted = Simulate("laser-plane", 1, 3.0);
  tilted.map.parameters["laser_theta"] = 0.1;  // not the simulator's beam
  const SmootherCrlb other_beam = ComputeSmootherCrlb(tilted);
  EXPECT_FALSE(other_beam.ok);
  EXPECT_NE(other_beam.reason.find("simulator"), std::string::npos) << other_beam.reason;
}

}  // namespace
}  // namespace mavloc
