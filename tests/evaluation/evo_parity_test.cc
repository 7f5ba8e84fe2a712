// Parity with evo (github.com/MichaelGrupp/evo) on two tiny TUM files, whose evo_ape / evo_rpe
// outputs are derived by hand below by following evo's code path line by line (evo cannot run
// here). The files:
//   ref.txt: 8 poses, t = 0.0, 0.1, ..., 0.7 s, identity orientation, positions
//            g = (0,0,0) (1,0,0) (2,0,0) (0,1,0) (1,1,0) (2,1,0) (3,0,0) (3,1,0);
//   est.txt: 7 poses, t_i = 0.1 i + 0.004 s (i < 6) and t = 5.0 s, positions
//            R0 (g_i + e_i) + t0 with e_i = (0, 0, a k_i), k = (1, -2, 1, -1, 2, -1), a = 0.01,
//            orientation R0 Rz(delta_i), delta_3 = 2 deg and 0 otherwise; R0 = Rz(30) Rx(20) deg,
//            t0 = (1, 2, 3).
// evo's path:
// 1. sync.associate_trajectories(ref, est, max_diff=0.01): est (7) is not longer than ref (8), so
//    est is walked (traj_short); each est stamp takes np.argmin |ref - t|: 0.004 -> 0.0, ...,
//    0.504 -> 0.5 (4 ms <= 10 ms); 5.0 -> 0.7 is 4.3 s away and dropped: 6 pairs (i = 0..5).
// 2. -a: trajectory.align -> geometry.umeyama_alignment(x = est positions, y = ref positions).
//    k is orthogonal to 1, x and y of the grid (sum k = 0, sum x k = 0 - 2 + 2 - 0 + 2 - 2 = 0,
//    sum y k = -1 + 2 - 1 = 0), so mean_x = R0 mean_g + t0 and
//    cov_xy = 1/n sum (g_i - mu)(g_i - mu + e_i)^T R0^T = C R0^T, C = diag(2/3, 1/4, 0)
//    (var x of 0,1,2,0,1,2 = 2/3; var y of 0,0,0,1,1,1 = 1/4; cov xy = 0). Its SVD is
//    I diag(2/3, 1/4, 0) R0^T: rank 2 (accepted), r = R0^T, t = -R0^T t0. The aligned estimate is
//    g_i + e_i with orientation Rz(delta_i).
// 3. APE trans_part: E = est_xyz - ref_xyz = e_i, errors a (1, 2, 1, 1, 2, 1):
//    rmse = a sqrt(12/6) = a sqrt 2, mean = 8a/6, median = a (sorted a a a a 2a 2a),
//    std = a sqrt((4 (1/3)^2 + 2 (2/3)^2) / 6) = a sqrt(2)/3, min a, max 2a, sse 12 a^2.
//    APE angle_deg: E = est^-1 ref = (Rz(-delta_i), ...): (0, 0, 0, 2, 0, 0) deg: rmse 2/sqrt 6,
//    mean 1/3, median 0, std sqrt(4/6 - 1/9) = sqrt(5)/3, max 2, sse 4.
//    APE rot_part: ||Rz(-2) - I||_F = 2 sqrt(2) sin(1 deg) at i = 3; full: sqrt(8 sin^2(delta/2)
//    + e_i^2) (E's translation -Rz(-delta) e_i has norm |e_i|).
// 4. RPE delta 1 frame, consecutive (filters.filter_pairs_by_index: ids 0..5, pairs (0,1)..(4,5)),
//    E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) with P the aligned estimate: translation
//    Rz(-delta_i)(dg + de) - dg: |de| = 3a, 3a, 2a for (0,1) (1,2) (2,3); for (3,4), delta_3 = 2
//    deg, dg = (1,0,0), de = (0,0,3a): (cos 2 - 1, -sin 2, 3a), norm sqrt(4 sin^2(1 deg) + 9a^2);
//    (4,5): 3a. angle_deg: 0, 0, 2, 2, 0.
// 5. -as (Sim3): c = trace(diag(d) S) / sigma_x = (11/12) / (11/12 + 2a^2) (sigma_x = var of the
//    est positions = var g + var e); the aligned estimate is mu_g + c (g_i - mu_g) + c e_i, so the
//    error is (c - 1)(g_i - mu_g) + c e_i, with |g_i - mu_g|^2 = 1.25, .25, 1.25, 1.25, .25, 1.25.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/rotation.h"
#include "datasets/io/tum_io.h"
#include "evaluation/trajectory_evaluation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

constexpr double kA = 0.01;
const double kK[6] = {1, -2, 1, -1, 2, -1};
const Eigen::Vector3d kGrid[8] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0},
                                  {1, 1, 0}, {2, 1, 0}, {3, 0, 0}, {3, 1, 0}};

void WriteLine(std::ofstream& out, double t, const Eigen::Vector3d& p,
               const Eigen::Quaterniond& q) {
  char line[256];
  std::snprintf(line, sizeof(line), "%.6f %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", t, p.x(),
                p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
  out << line;
}

struct Files {
  std::string ref, est;
};

// The two files; the estimate's stamps shifted by stamp_shift_s (for the --t_offset case).
Files WriteFiles(double stamp_shift_s = 0.0) {
  const std::string dir = testing::MakeTempDir();
  Files files{dir + "/ref.txt", dir + "/est.txt"};
  std::ofstream ref(files.ref), est(files.est);
  ref << "# timestamp tx ty tz qx qy qz qw\n";
  for (int i = 0; i < 8; ++i) WriteLine(ref, 0.1 * i, kGrid[i], Eigen::Quaterniond::Identity());
  const Eigen::Matrix3d R0 = Rz(30 * kDeg) * Rx(20 * kDeg);
  const Eigen::Vector3d t0(1, 2, 3);
  for (int i = 0; i < 6; ++i) {
    const double delta = i == 3 ? 2 * kDeg : 0.0;
    WriteLine(est, 0.1 * i + 0.004 + stamp_shift_s,
              R0 * (kGrid[i] + Eigen::Vector3d(0, 0, kA * kK[i])) + t0,
              Eigen::Quaterniond(R0 * Rz(delta)));
  }
  WriteLine(est, 5.0 + stamp_shift_s, Eigen::Vector3d(7, 7, 7), Eigen::Quaterniond::Identity());
  return files;
}

void ExpectRel(double actual, double expected, double rel = 1e-9) {
  EXPECT_NEAR(actual, expected, rel * std::max(1e-12, std::abs(expected)));
}

TEST(EvoParity, ApeAndRpeWithSe3Alignment) {
  const Files files = WriteFiles();
  EvaluationProtocol protocol;  // evo defaults: nearest, max_diff 0.01 s, se3 (-a), delta 1 frame
  const auto r =
      EvaluateTrajectory(ReadTumTrajectory(files.est), ReadTumTrajectory(files.ref), protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->pair_count, 6u);

  // APE trans_part (step 3).
  const ErrorStatistics& t = r->ape_translation_m;
  ExpectRel(t.rmse, kA * std::sqrt(2.0));
  ExpectRel(t.mean, 8.0 * kA / 6.0);
  ExpectRel(t.median, kA);
  ExpectRel(t.std, kA * std::sqrt(2.0) / 3.0, 1e-6);
  ExpectRel(t.min, kA);
  ExpectRel(t.max, 2 * kA);
  ExpectRel(t.sse, 12 * kA * kA);
  // APE angle_deg.
  const ErrorStatistics& a = r->ape_rotation_deg;
  ExpectRel(a.rmse, 2.0 / std::sqrt(6.0));
  ExpectRel(a.mean, 1.0 / 3.0);
  EXPECT_NEAR(a.median, 0.0, 1e-9);
  ExpectRel(a.std, std::sqrt(5.0) / 3.0);
  ExpectRel(a.max, 2.0);
  ExpectRel(a.sse, 4.0);
  // APE rot_part and full at pair 3.
  ExpectRel(r->ape.rotation_part[3], 2 * std::sqrt(2.0) * std::sin(1 * kDeg));
  ExpectRel(r->ape.full[3], std::sqrt(8 * std::pow(std::sin(1 * kDeg), 2) + kA * kA));
  ExpectRel(r->ape.full[1], 2 * kA, 1e-6);

  // RPE delta 1 frame (step 4).
  ASSERT_EQ(r->rpe.size(), 1u);
  const auto& rpe = r->rpe[0];
  ASSERT_EQ(rpe.errors.size(), 5u);
  const double e34 = std::sqrt(4 * std::pow(std::sin(1 * kDeg), 2) + 9 * kA * kA);
  const double expected[5] = {3 * kA, 3 * kA, 2 * kA, e34, 3 * kA};
  double sum = 0.0, sum_sq = 0.0;
  for (int k = 0; k < 5; ++k) {
    ExpectRel(rpe.errors[k].translation_m, expected[k], 1e-7);
    sum += expected[k];
    sum_sq += expected[k] * expected[k];
  }
  ExpectRel(rpe.translation_m.rmse, std::sqrt(sum_sq / 5), 1e-7);
  ExpectRel(rpe.translation_m.mean, sum / 5, 1e-7);
  ExpectRel(rpe.translation_m.median, 3 * kA, 1e-7);
  ExpectRel(rpe.translation_m.max, e34, 1e-7);
  ExpectRel(rpe.rotation_deg.rmse, std::sqrt(8.0 / 5.0), 1e-7);
  ExpectRel(rpe.rotation_deg.mean, 0.8, 1e-7);
  EXPECT_NEAR(rpe.rotation_deg.median, 0.0, 1e-6);
}

TEST(EvoParity, TimeOffsetGivesTheSameNumbers) {
  // The estimate's stamps 2 s later, --t_offset -2: the same six pairs and statistics.
  const Files files = WriteFiles(2.0);
  EvaluationProtocol protocol;
  protocol.time_offset_s = -2.0;
  const auto r =
      EvaluateTrajectory(ReadTumTrajectory(files.est), ReadTumTrajectory(files.ref), protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->pair_count, 6u);
  ExpectRel(r->ape_translation_m.rmse, kA * std::sqrt(2.0));
  // Without the offset nothing pairs.
  protocol.time_offset_s = 0.0;
  EXPECT_FALSE(
      EvaluateTrajectory(ReadTumTrajectory(files.est), ReadTumTrajectory(files.ref), protocol)
          .has_value());
}

TEST(EvoParity, Sim3Alignment) {
  const Files files = WriteFiles();
  EvaluationProtocol protocol;
  protocol.alignment = AlignmentMode::kSim3;  // evo -as
  const auto r =
      EvaluateTrajectory(ReadTumTrajectory(files.est), ReadTumTrajectory(files.ref), protocol);
  ASSERT_TRUE(r.has_value());
  const double c = (11.0 / 12.0) / (11.0 / 12.0 + 2 * kA * kA);
  ExpectRel(r->alignment.scale, c);
  const double d2[6] = {1.25, 0.25, 1.25, 1.25, 0.25, 1.25};
  double sum_sq = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double e2 = (c - 1) * (c - 1) * d2[i] + c * c * kA * kA * kK[i] * kK[i];
    ExpectRel(r->ape.translation_m[i], std::sqrt(e2), 1e-7);
    sum_sq += e2;
  }
  ExpectRel(r->ape_translation_m.rmse, std::sqrt(sum_sq / 6), 1e-7);
  ExpectRel(r->ape_translation_m.sse, sum_sq, 1e-7);
}

}  // namespace
}  // namespace mavloc
