// The marginal prior of a smoother window (solver/smoother/smoother_marginalization.h) is the Schur
// complement of the eliminated residuals: checked against a dense computation on a random chain
// problem; a residual that touches a free block outside the keyframes is refused.
#include "solver/smoother/smoother_marginalization.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

// r = A [x_1; ...; x_k] + b over the ambient coordinates of its blocks.
class LinearFactor : public ceres::CostFunction {
 public:
  LinearFactor(const std::vector<int>& sizes, Rng& rng) {
    int columns = 0;
    for (int size : sizes) {
      mutable_parameter_block_sizes()->push_back(size);
      columns += size;
    }
    set_num_residuals(6);
    A_ = Eigen::MatrixXd(6, columns);
    b_ = Eigen::VectorXd(6);
    for (int i = 0; i < 6; ++i) {
      b_[i] = rng.Uniform(-1.0, 1.0);
      for (int j = 0; j < columns; ++j) A_(i, j) = rng.Uniform(-1.0, 1.0);
    }
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, 6);
    r = b_;
    int column = 0;
    for (size_t k = 0; k < parameter_block_sizes().size(); ++k) {
      const int size = parameter_block_sizes()[k];
      r += A_.middleCols(column, size) * Eigen::Map<const Eigen::VectorXd>(parameters[k], size);
      if (jacobians && jacobians[k]) {
        Eigen::Map<Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[k], 6,
                                                                                size);
        J = A_.middleCols(column, size);
      }
      column += size;
    }
    return true;
  }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd b_;
};

// n keyframes' parameter blocks (q on Ceres' quaternion manifold, p, v, b_g, b_a) in a problem:
// random states drawn from rng when given, else the identity and zeros.
struct KeyframeChain {
  KeyframeChain(int n, Rng* rng) : storage(n), problem(ProblemOptions()) {
    for (auto& s : storage) {
      s = {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
      if (rng) {
        const Eigen::Quaterniond q = ExpQuaternion(rng->Gaussian3(1.0));
        s = {q.x(), q.y(), q.z(), q.w()};
        for (int i = 4; i < 16; ++i) s[i] = rng->Uniform(-1.0, 1.0);
      }
      KeyframeBlockPointers b{s.data(), s.data() + 4, s.data() + 7, s.data() + 10, s.data() + 13};
      problem.AddParameterBlock(b[0], 4, &quaternion);
      for (int i = 1; i < 5; ++i) problem.AddParameterBlock(b[i], 3);
      keyframes.push_back(b);
    }
  }
  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options options;
    options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return options;
  }
  std::vector<std::array<double, 16>> storage;
  ceres::EigenQuaternionManifold quaternion;
  ceres::Problem problem;
  std::vector<KeyframeBlockPointers> keyframes;
};

TEST(SmootherMarginalization, PriorIsTheSchurComplementOfTheEliminatedResiduals) {
  Rng rng(3);
  constexpr int kKeyframes = 6, kM = 4;
  KeyframeChain chain(kKeyframes, &rng);
  ceres::Problem& problem = chain.problem;
  const std::vector<KeyframeBlockPointers>& keyframes = chain.keyframes;
  // Per keyframe three unary factors over all its blocks, and a chain factor to the next one
  // (over q, p, v of both and the biases of the first): every eliminated state is determined;
  // keyframe m's biases are touched by no eliminated residual (their rows of the prior are zero).
  std::vector<ceres::ResidualBlockId> eliminated;
  for (int k = 0; k < kKeyframes; ++k) {
    const KeyframeBlockPointers& b = keyframes[k];
    for (int i = 0; i < 3; ++i) {
      const auto id = problem.AddResidualBlock(new LinearFactor({4, 3, 3, 3, 3}, rng), nullptr,
                                               b[0], b[1], b[2], b[3], b[4]);
      if (k < kM) eliminated.push_back(id);
    }
    if (k + 1 == kKeyframes) continue;
    const KeyframeBlockPointers& c = keyframes[k + 1];
    const auto id =
        problem.AddResidualBlock(new LinearFactor({4, 3, 3, 3, 3, 4, 3, 3}, rng), nullptr, b[0],
                                 b[1], b[2], b[3], b[4], c[0], c[1], c[2]);
    if (k < kM) eliminated.push_back(id);
  }
  std::string why;
  const auto prior = MarginalizeKeyframes(&problem, keyframes, kM, 1, &why);
  ASSERT_TRUE(prior) << why;

  // Dense reference: J over keyframes 0..m of the eliminated residuals, H = J^T J, g = J^T r.
  ceres::Problem::EvaluateOptions evaluate;
  for (int k = 0; k <= kM; ++k)
    for (double* block : keyframes[k]) evaluate.parameter_blocks.push_back(block);
  evaluate.residual_blocks = eliminated;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  double cost = 0.0;
  ASSERT_TRUE(problem.Evaluate(evaluate, &cost, &residuals, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int i = crs.rows[row]; i < crs.rows[row + 1]; ++i) J(row, crs.cols[i]) = crs.values[i];
  const Eigen::VectorXd r = Eigen::Map<Eigen::VectorXd>(residuals.data(), residuals.size());
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::VectorXd g = J.transpose() * r;
  const int o = 15 * kM;
  const Eigen::MatrixXd H_oo_inv = H.topLeftCorner(o, o).inverse();
  const Eigen::MatrixXd H_m =
      H.bottomRightCorner(15, 15) - H.bottomLeftCorner(15, o) * H_oo_inv * H.topRightCorner(o, 15);
  const Eigen::VectorXd g_m = g.tail(15) - H.bottomLeftCorner(15, o) * H_oo_inv * g.head(o);
  const Matrix15d& R = prior->sqrt_information;
  EXPECT_LT((R.transpose() * R - H_m).norm(), 1e-9 * H_m.norm());
  EXPECT_EQ((H_m.bottomRightCorner<6, 6>().norm()), 0.0);
  EXPECT_LT((R.transpose() * prior->offset - g_m).norm(), 1e-9 * (1.0 + g_m.norm()));
  // The linearization point is keyframe m's state.
  EXPECT_EQ(prior->linearization.p_W, Eigen::Vector3d(keyframes[kM][1]));

  // A free block outside the keyframes that an eliminated residual touches cannot be carried.
  std::array<double, 3> landmark{0.0, 0.0, 0.0};
  problem.AddResidualBlock(new LinearFactor({3, 3}, rng), nullptr, keyframes[1][1],
                           landmark.data());
  EXPECT_FALSE(MarginalizeKeyframes(&problem, keyframes, kM, 1, &why));
  EXPECT_NE(why.find("not a keyframe state"), std::string::npos) << why;
}

// The elimination runs along the chain: a residual between keyframes that are not consecutive
// is refused (it would need fill the block elimination does not carry), and so is an eliminated
// state that no residual determines.
TEST(SmootherMarginalization, RefusesWhatIsNotAChain) {
  Rng rng(4);
  KeyframeChain chain(4, nullptr);
  ceres::Problem& problem = chain.problem;
  const std::vector<KeyframeBlockPointers>& keyframes = chain.keyframes;
  // Keyframe 0's velocity and biases are touched by nothing: not determined.
  problem.AddResidualBlock(new LinearFactor({4, 3}, rng), nullptr, keyframes[0][0],
                           keyframes[0][1]);
  problem.AddResidualBlock(new LinearFactor({3, 3}, rng), nullptr, keyframes[0][1],
                           keyframes[1][1]);
  std::string why;
  EXPECT_FALSE(MarginalizeKeyframes(&problem, keyframes, 2, 1, &why));
  EXPECT_NE(why.find("not determined"), std::string::npos) << why;
  // Keyframes 0 and 2 coupled directly.
  problem.AddResidualBlock(new LinearFactor({3, 3}, rng), nullptr, keyframes[0][2],
                           keyframes[2][2]);
  why.clear();
  EXPECT_FALSE(MarginalizeKeyframes(&problem, keyframes, 3, 1, &why));
  EXPECT_NE(why.find("keyframes 0 and 2, which are not consecutive"), std::string::npos) << why;
}

}  // namespace
}  // namespace mavloc
