// The analytic preintegrated IMU factor (ImuFactor) against its automatic-differentiation twin
// (ImuFactorAutoDiff) and against central differences on the manifold, on random keyframe states,
// random biases away from the linearization point and random preintegrations (fixed seeds),
// including a near-identity case (the Taylor branches of Log, Jr and Jr^-1) and ~170 deg rotations
// (of the preintegrated motion and of the residual itself).
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/random.h"
#include "core/rotation.h"
#include "solver/smoother/imu_preintegration.h"
#include "solver/smoother/residuals/imu_factor.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr int kBlockSizes[8] = {4, 3, 3, 3, 3, 4, 3, 3};
bool IsQuaternion(int b) { return b == 0 || b == 5; }

// A random, smoothly varying IMU stream at 100 Hz over [0, duration_s]: a constant turn rate
// `omega` plus random wiggles of amplitude `wiggle` (rad/s), and a random specific force around
// hover.
std::vector<ImuSample> RandomStream(Rng& rng, const Eigen::Vector3d& omega, double wiggle,
                                    double duration_s) {
  const Eigen::Vector3d w_amp = rng.Gaussian3(wiggle), w_freq = rng.Gaussian3(3.0),
                        w_phase = rng.Gaussian3(1.0);
  const Eigen::Vector3d a0 = Eigen::Vector3d(0, 0, 9.81) + rng.Gaussian3(0.5);
  const Eigen::Vector3d a_amp = rng.Gaussian3(1.0), a_freq = rng.Gaussian3(4.0),
                        a_phase = rng.Gaussian3(1.0);
  std::vector<ImuSample> samples;
  for (int k = 0; k * 0.01 <= duration_s + 1e-9; ++k) {
    const double t = 0.01 * k;
    ImuSample s;
    s.t_ns = SecondsToNs(t);
    for (int a = 0; a < 3; ++a) {
      s.gyro_rad_s[a] = omega[a] + w_amp[a] * std::sin(w_freq[a] * t + w_phase[a]);
      s.accel_m_s2[a] = a0[a] + a_amp[a] * std::sin(a_freq[a] * t + a_phase[a]);
    }
    samples.push_back(s);
  }
  return samples;
}

struct Case {
  std::string name;
  std::unique_ptr<ImuPreintegration> pre;
  Eigen::Matrix<double, 9, 9> L;
  std::vector<std::vector<double>> values;  // the 8 parameter blocks

  std::vector<double*> Pointers() {
    std::vector<double*> p;
    for (auto& v : values) p.push_back(v.data());
    return p;
  }
};

std::vector<double> Coefficients(const Eigen::Quaterniond& q) {
  return {q.x(), q.y(), q.z(), q.w()};
}
std::vector<double> Coefficients(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Options of a random case.
struct CaseSpec {
  std::string name;
  uint64_t seed = 1;
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // constant turn rate of the stream
  double wiggle = 0.5;                              // rad/s
  double dt_s = 0.4;                                // between the keyframes
  double attitude_scale = 1.0;                      // of the random R_i (rad, per axis)
  double gyro_bias0 = 5e-3;                         // linearization gyro bias b0 (rad/s)
  double gyro_bias_offset = 1e-2;                   // b_g - b0 (rad/s, per axis)
  double accel_bias_offset = 5e-2;                  // b_a - b0 (m/s^2, per axis)
  // The state j: the prediction from i, then R_j <- R_j Exp(rotation_error) and
  // p_j, v_j moved by Gaussian offsets of these sizes.
  Eigen::Vector3d rotation_error = Eigen::Vector3d::Zero();
  double random_rotation_error = 0.3;  // rad, per axis, added to rotation_error
  double translation_error = 0.2;      // m and m/s, per axis
};

Case MakeCase(const CaseSpec& spec) {
  Rng rng(spec.seed);
  Case c;
  c.name = spec.name;
  const std::vector<ImuSample> samples =
      RandomStream(rng, spec.omega, spec.wiggle, spec.dt_s + 0.3);
  ImuNoise noise;
  noise.gyroscope_noise_density = 1.7e-4 * (1.0 + rng.Uniform());
  noise.accelerometer_noise_density = 2e-3 * (1.0 + rng.Uniform());
  ImuBiases b0;
  b0.b_g = rng.Gaussian3(spec.gyro_bias0);
  b0.b_a = rng.Gaussian3(5e-2);
  c.pre = std::make_unique<ImuPreintegration>(samples, SecondsToNs(0.105),
                                              SecondsToNs(0.105 + spec.dt_s), b0, noise);
  c.L = c.pre->SqrtInformation();

  ImuKeyframeState s_i;
  s_i.q_W_B = ExpQuaternion(rng.Gaussian3(spec.attitude_scale));
  s_i.p_W = rng.Gaussian3(3.0);
  s_i.v_W = rng.Gaussian3(1.0);
  s_i.biases.b_g = b0.b_g + rng.Gaussian3(spec.gyro_bias_offset);
  s_i.biases.b_a = b0.b_a + rng.Gaussian3(spec.accel_bias_offset);
  ImuKeyframeState s_j = c.pre->Predict(s_i);
  const Eigen::Vector3d rotation_error =
      spec.rotation_error + rng.Gaussian3(spec.random_rotation_error);
  s_j.q_W_B = (s_j.q_W_B * ExpQuaternion(rotation_error)).normalized();
  s_j.p_W += rng.Gaussian3(spec.translation_error);
  s_j.v_W += rng.Gaussian3(spec.translation_error);

  c.values = {Coefficients(s_i.q_W_B),      Coefficients(s_i.p_W),        Coefficients(s_i.v_W),
              Coefficients(s_i.biases.b_g), Coefficients(s_i.biases.b_a), Coefficients(s_j.q_W_B),
              Coefficients(s_j.p_W),        Coefficients(s_j.v_W)};
  return c;
}

// Residual and ambient Jacobians of a cost function.
struct Evaluation {
  Eigen::Matrix<double, 9, 1> r;
  std::vector<Matrix> J;  // ambient, 9 x block size
};

Evaluation Evaluate(const ceres::CostFunction& cost, Case& c, bool with_jacobians = true) {
  Evaluation e;
  std::vector<double*> jacobian_ptrs;
  for (int b = 0; b < 8; ++b) {
    e.J.emplace_back(Matrix::Zero(9, kBlockSizes[b]));
    jacobian_ptrs.push_back(e.J.back().data());
  }
  const std::vector<double*> p = c.Pointers();
  EXPECT_TRUE(cost.Evaluate(p.data(), e.r.data(), with_jacobians ? jacobian_ptrs.data() : nullptr));
  return e;
}

// The manifold's PlusJacobian of block b (identity for the vector blocks).
Eigen::MatrixXd PlusJacobian(const Case& c, int b) {
  if (!IsQuaternion(b)) return Eigen::MatrixXd::Identity(3, 3);
  static const ceres::EigenQuaternionManifold manifold;
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> P;
  manifold.PlusJacobian(c.values[b].data(), P.data());
  return P;
}

// Central differences of the residual in block b's tangent space: x [+] delta is the manifold's
// Plus for the quaternions.
Eigen::MatrixXd NumericTangentJacobian(const ceres::CostFunction& cost, Case& c, int b) {
  static const ceres::EigenQuaternionManifold manifold;
  const std::vector<double> x0 = c.values[b];
  auto f = [&](const Eigen::VectorXd& delta) -> Eigen::VectorXd {
    Case moved;
    moved.values = c.values;
    if (IsQuaternion(b)) {
      manifold.Plus(x0.data(), delta.data(), moved.values[b].data());
    } else {
      for (int k = 0; k < 3; ++k) moved.values[b][k] = x0[k] + delta[k];
    }
    return Evaluate(cost, moved, false).r;
  };
  auto minus = [](const Eigen::VectorXd& a, const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return a - d;
  };
  return testing::CentralDifferenceJacobian(f, 3, minus, 1e-6);
}

double MaxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

// The largest relative differences seen by a test (printed at its end).
struct Worst {
  double residual = 0.0, numeric = 0.0, autodiff = 0.0;
  void Print() const {
    std::printf(
        "largest relative differences: residual %.1e, Jacobian vs central differences "
        "%.1e, vs autodiff %.1e\n",
        residual, numeric, autodiff);
  }
};

// [r_R; r_v; r_p] from the whitened residual L [r_R; r_v; r_p] (L is upper triangular).
Eigen::Matrix<double, 9, 1> Unwhiten(const Case& c, const Eigen::Matrix<double, 9, 1>& r) {
  return c.L.triangularView<Eigen::Upper>().solve(r);
}

// The three checks of the analytic factor on one case.
void ExpectAnalyticFactorCorrect(Case& c, Worst& worst) {
  SCOPED_TRACE(c.name);
  std::unique_ptr<ceres::CostFunction> analytic(ImuFactor::Create(*c.pre, c.L));
  std::unique_ptr<ceres::CostFunction> autodiff(ImuFactorAutoDiff::Create(*c.pre, c.L));
  const Evaluation a = Evaluate(*analytic, c);
  const Evaluation d = Evaluate(*autodiff, c);

  // (a) The same residual [r_R; r_v; r_p] (rad, m/s, m; before the whitening, which multiplies
  // the rounding errors by up to |L| ~ 1e4), to 1e-12 relative to its size (absolute below 1).
  const Eigen::Matrix<double, 9, 1> raw_a = Unwhiten(c, a.r), raw_d = Unwhiten(c, d.r);
  const double residual_scale = std::max(1.0, raw_d.cwiseAbs().maxCoeff());
  worst.residual = std::max(worst.residual, MaxAbs(raw_a - raw_d) / residual_scale);
  EXPECT_LT(MaxAbs(raw_a - raw_d), 1e-12 * residual_scale)
      << "analytic " << raw_a.transpose() << "\nautodiff " << raw_d.transpose();
  // Residual-only evaluation gives the same residual.
  EXPECT_EQ(Evaluate(*analytic, c, false).r, a.r);

  for (int b = 0; b < 8; ++b) {
    SCOPED_TRACE("block " + std::to_string(b));
    const Eigen::MatrixXd P = PlusJacobian(c, b);
    const Eigen::MatrixXd J_analytic = a.J[b] * P;
    const Eigen::MatrixXd J_autodiff = d.J[b] * P;
    const Eigen::MatrixXd J_numeric = NumericTangentJacobian(*analytic, c, b);
    const double scale = std::max(MaxAbs(J_autodiff), 1e-300);
    worst.numeric = std::max(worst.numeric, MaxAbs(J_numeric - J_analytic) / scale);
    worst.autodiff = std::max(worst.autodiff, MaxAbs(J_autodiff - J_analytic) / scale);
    // (b) Central differences on the manifold, ~1e-6 relative.
    EXPECT_LT(MaxAbs(J_numeric - J_analytic), 1e-6 * scale) << "analytic\n"
                                                            << J_analytic << "\nnumeric\n"
                                                            << J_numeric;
    // (c) Automatic differentiation, 1e-9 relative.
    EXPECT_LT(MaxAbs(J_autodiff - J_analytic), 1e-9 * scale) << "analytic\n"
                                                             << J_analytic << "\nautodiff\n"
                                                             << J_autodiff;
    if (IsQuaternion(b)) {
      // The ambient Jacobian has no component along q (the pseudo-inverse of P).
      const Eigen::Map<const Eigen::Vector4d> q(c.values[b].data());
      EXPECT_LT((a.J[b] * q).cwiseAbs().maxCoeff(), 1e-12 * scale);
    }
  }

  // A block asked for alone (Ceres passes null for constant blocks) is the same block.
  for (int b = 0; b < 8; ++b) {
    std::vector<double*> jacobian_ptrs(8, nullptr);
    Matrix J_alone = Matrix::Zero(9, kBlockSizes[b]);
    jacobian_ptrs[b] = J_alone.data();
    Eigen::Matrix<double, 9, 1> r;
    const std::vector<double*> p = c.Pointers();
    ASSERT_TRUE(analytic->Evaluate(p.data(), r.data(), jacobian_ptrs.data()));
    EXPECT_EQ(J_alone, a.J[b]) << "block " << b;
  }
}

double ResidualAngle(Case& c) {
  std::unique_ptr<ceres::CostFunction> analytic(ImuFactor::Create(*c.pre, c.L));
  return Unwhiten(c, Evaluate(*analytic, c, false).r).head<3>().norm();
}

TEST(ImuFactorJacobianTest, RandomStatesBiasesAndPreintegrations) {
  Worst worst;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    CaseSpec spec;
    spec.name = "random seed " + std::to_string(seed);
    spec.seed = seed;
    spec.omega = Rng(1000 + seed).Gaussian3(0.5);
    spec.dt_s = 0.1 + 0.05 * static_cast<double>(seed % 10);
    // Rotation residuals and bias corrections on both sides of the small-angle branches (1e-2).
    spec.random_rotation_error = std::vector<double>{0.3, 1e-2, 3e-3}[seed % 3];
    spec.gyro_bias_offset = seed % 2 ? 1e-2 : 5e-2;
    Case c = MakeCase(spec);
    ExpectAnalyticFactorCorrect(c, worst);
  }
  worst.Print();
}

TEST(ImuFactorJacobianTest, ConsistentStateNearZeroResidual) {
  // The state j predicted from i with the factor's own biases: r ~ 0, every Jacobian still exact.
  Worst worst;
  for (uint64_t seed = 31; seed <= 35; ++seed) {
    CaseSpec spec;
    spec.name = "consistent seed " + std::to_string(seed);
    spec.seed = seed;
    spec.random_rotation_error = 0.0;
    spec.translation_error = 0.0;
    Case c = MakeCase(spec);
    EXPECT_LT(ResidualAngle(c), 1e-3);
    ExpectAnalyticFactorCorrect(c, worst);
  }
  worst.Print();
}

TEST(ImuFactorJacobianTest, NearIdentityRotations) {
  // No turn (a zero linearization gyro bias), R_i ~ I, b_g = b0 (J_R_bg db_g = 0 exactly) and
  // r_R ~ 1e-9 rad: the small-angle branches of Log, Exp, Jr and Jr^-1.
  Worst worst;
  CaseSpec spec;
  spec.name = "near identity";
  spec.seed = 41;
  spec.wiggle = 1e-7;
  spec.gyro_bias0 = 0.0;
  spec.attitude_scale = 1e-8;
  spec.gyro_bias_offset = 0.0;
  spec.random_rotation_error = 1e-9;
  spec.translation_error = 1e-3;
  Case c = MakeCase(spec);
  // b_g = b0 exactly: the correction is the identity.
  c.values[3] = Coefficients(Eigen::Vector3d(c.pre->linearization_biases().b_g));
  EXPECT_LT(ResidualAngle(c), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(c.pre->delta_q()).angle(), 1e-6);
  ExpectAnalyticFactorCorrect(c, worst);

  // And a tiny gyro-bias offset (Jr's Taylor branch with a non-zero argument).
  spec.name = "near identity, tiny gyro bias offset";
  spec.gyro_bias_offset = 1e-9;
  Case c2 = MakeCase(spec);
  ExpectAnalyticFactorCorrect(c2, worst);
  worst.Print();
}

TEST(ImuFactorJacobianTest, LargeRotations) {
  Worst worst;
  // ~170 deg turned between the keyframes (dR large, r_R small).
  {
    CaseSpec spec;
    spec.name = "170 deg preintegrated turn";
    spec.seed = 51;
    spec.omega = Eigen::Vector3d(1, -2, 0.5).normalized() * (170.0 * M_PI / 180.0);
    spec.wiggle = 0.05;
    spec.dt_s = 1.0;
    spec.attitude_scale = 2.0;
    spec.random_rotation_error = 0.05;
    Case c = MakeCase(spec);
    EXPECT_NEAR(Eigen::AngleAxisd(c.pre->delta_q()).angle(), 170.0 * M_PI / 180.0, 0.2);
    ExpectAnalyticFactorCorrect(c, worst);
  }
  // A ~170 deg rotation residual (Jr^-1 far from the identity).
  for (uint64_t seed = 61; seed <= 63; ++seed) {
    CaseSpec spec;
    spec.name = "170 deg residual seed " + std::to_string(seed);
    spec.seed = seed;
    spec.omega = Eigen::Vector3d(0.3, 0.2, -0.4);
    Rng axis_rng(seed);
    spec.rotation_error = axis_rng.Gaussian3(1.0).normalized() * (170.0 * M_PI / 180.0);
    spec.random_rotation_error = 0.0;
    Case c = MakeCase(spec);
    EXPECT_NEAR(ResidualAngle(c), 170.0 * M_PI / 180.0, 0.1);
    ExpectAnalyticFactorCorrect(c, worst);
  }
  worst.Print();
}

}  // namespace
}  // namespace mavloc
