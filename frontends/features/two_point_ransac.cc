#include "frontends/features/two_point_ransac.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {

namespace {

// A usable match with what every hypothesis needs precomputed.
struct TwoPointMatch {
  Eigen::Vector3d g;   // R_C1_C0 f0
  Eigen::Vector3d f1;  // unit
  Eigen::Vector3d n;   // g x f1, the normal of (1)
  double e_R = 0.0;    // (4)
  size_t index = 0;    // into the input
};

// The MSAC cost (6) of t and of -t, with their inlier and parallax-inlier counts.
struct TwoPointSignedScore {
  double cost[2] = {0.0, 0.0};  // [0]: +t, [1]: -t
  int inliers[2] = {0, 0};
  int parallax_inliers[2] = {0, 0};
};

// e_t^2 of (3) for a unit t; a match on the epipole (t parallel to both bearings) has zero error.
double TwoPointSquaredError(const TwoPointMatch& m, const Eigen::Vector3d& t,
                            Eigen::Vector3d* a_out, Eigen::Vector3d* b_out) {
  *a_out = t.cross(m.g);
  *b_out = t.cross(m.f1);
  const double e = t.dot(m.n);
  const double s2 = a_out->squaredNorm() + b_out->squaredNorm();
  if (!(s2 > 0.0)) return 0.0;
  return e * e / s2;
}

// Whether match m is an inlier of +t (sign 0) and of -t (sign 1), by (3)-(5).
void TwoPointInlierOfSigns(const TwoPointMatch& m, const Eigen::Vector3d& t, double threshold,
                           bool inlier[2], double* e2) {
  Eigen::Vector3d a, b;
  *e2 = TwoPointSquaredError(m, t, &a, &b);
  inlier[0] = inlier[1] = false;
  if (*e2 > threshold * threshold) return;
  if (m.e_R <= threshold) {
    inlier[0] = inlier[1] = true;
    return;
  }
  // Depth signs (5) for +t; both flip with t.
  const double lambda0 = -b.dot(m.n), lambda1 = -a.dot(m.n);
  inlier[0] = lambda0 > 0.0 && lambda1 > 0.0;
  inlier[1] = lambda0 < 0.0 && lambda1 < 0.0;
}

TwoPointSignedScore TwoPointScore(const std::vector<TwoPointMatch>& matches,
                                  const Eigen::Vector3d& t, double threshold) {
  TwoPointSignedScore s;
  const double cap = threshold * threshold;
  for (const TwoPointMatch& m : matches) {
    bool inlier[2];
    double e2;
    TwoPointInlierOfSigns(m, t, threshold, inlier, &e2);
    for (int k = 0; k < 2; ++k) {
      if (inlier[k]) {
        s.cost[k] += e2;
        ++s.inliers[k];
        if (m.e_R > threshold) ++s.parallax_inliers[k];
      } else {
        s.cost[k] += cap;
      }
    }
  }
  return s;
}

// A signed hypothesis and its score.
struct TwoPointHypothesis {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();  // unit, sign chosen
  double cost = std::numeric_limits<double>::infinity();
  int inliers = 0;
  int parallax_inliers = 0;
};

TwoPointHypothesis TwoPointBestSign(const std::vector<TwoPointMatch>& matches,
                                    const Eigen::Vector3d& t, double threshold) {
  const TwoPointSignedScore s = TwoPointScore(matches, t, threshold);
  const int k = s.cost[1] < s.cost[0] ? 1 : 0;
  return {k == 0 ? t : Eigen::Vector3d(-t), s.cost[k], s.inliers[k], s.parallax_inliers[k]};
}

// M of (8) over the inliers of the signed t.
Eigen::Matrix3d TwoPointScatter(const std::vector<TwoPointMatch>& matches, const Eigen::Vector3d& t,
                                double threshold) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (const TwoPointMatch& m : matches) {
    bool inlier[2];
    double e2;
    TwoPointInlierOfSigns(m, t, threshold, inlier, &e2);
    if (!inlier[0]) continue;
    const double s2 = t.cross(m.g).squaredNorm() + t.cross(m.f1).squaredNorm();
    M += m.n * m.n.transpose() / std::max(s2, 1e-12);
  }
  return M;
}

// The refit (8) of a hypothesis, rounds times at most, each kept only when it lowers the MSAC
// cost (6).
TwoPointHypothesis TwoPointRefit(const std::vector<TwoPointMatch>& matches, TwoPointHypothesis best,
                                 double threshold, int rounds) {
  for (int round = 0; round < rounds && best.inliers > 0; ++round) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(
        TwoPointScatter(matches, best.t, threshold));
    Eigen::Vector3d t = eigen.eigenvectors().col(0);
    if (t.dot(best.t) < 0.0) t = -t;
    const TwoPointHypothesis refit = TwoPointBestSign(matches, t, threshold);
    if (!(refit.cost <= best.cost)) break;
    const bool same = refit.inliers == best.inliers && refit.t.dot(best.t) > 1.0 - 1e-12;
    best = refit;
    if (same) break;
  }
  return best;
}

std::vector<bool> TwoPointMask(const std::vector<TwoPointMatch>& matches, size_t count,
                               const Eigen::Vector3d& t, double threshold) {
  std::vector<bool> mask(count, false);
  for (const TwoPointMatch& m : matches) {
    bool inlier[2];
    double e2;
    TwoPointInlierOfSigns(m, t, threshold, inlier, &e2);
    mask[m.index] = inlier[0];
  }
  return mask;
}

}  // namespace

std::string_view EpipolarRansacStatusName(EpipolarRansacStatus status) {
  switch (status) {
    case EpipolarRansacStatus::kOk:
      return "ok";
    case EpipolarRansacStatus::kPureRotation:
      return "pure rotation";
    case EpipolarRansacStatus::kTooFewMatches:
      return "too few matches";
    case EpipolarRansacStatus::kDegenerate:
      return "degenerate";
    case EpipolarRansacStatus::kNoConsensus:
      return "no consensus";
    case EpipolarRansacStatus::kInvalidInput:
      return "invalid input";
  }
  return "unknown";
}

double EpipolarSampsonError(const Eigen::Vector3d& f_C0, const Eigen::Vector3d& f_C1,
                            const Eigen::Matrix3d& R_C1_C0, const Eigen::Vector3d& t_C1_C0) {
  TwoPointMatch m;
  m.g = R_C1_C0 * f_C0;
  m.f1 = f_C1;
  m.n = m.g.cross(m.f1);
  Eigen::Vector3d a, b;
  return std::sqrt(TwoPointSquaredError(m, t_C1_C0.normalized(), &a, &b));
}

double RotationOnlyError(const Eigen::Vector3d& f_C0, const Eigen::Vector3d& f_C1,
                         const Eigen::Matrix3d& R_C1_C0) {
  const Eigen::Vector3d g = R_C1_C0 * f_C0;
  return std::atan2(g.cross(f_C1).norm(), g.dot(f_C1)) / std::sqrt(2.0);
}

int RansacIterations(double confidence, double inlier_share, int sample_size, int max_iterations) {
  const double all_inlier = std::pow(std::clamp(inlier_share, 0.0, 1.0), sample_size);
  if (all_inlier >= 1.0) return std::min(1, max_iterations);
  if (all_inlier <= 0.0) return max_iterations;
  const double n = std::log(1.0 - confidence) / std::log1p(-all_inlier);
  if (!(n < static_cast<double>(max_iterations))) return max_iterations;
  return std::max(1, static_cast<int>(std::ceil(n)));
}

bool StartEpipolarResult(const std::vector<Eigen::Vector3d>& f_C0,
                         const std::vector<Eigen::Vector3d>& f_C1, EpipolarRansacResult* out) {
  if (f_C0.size() != f_C1.size()) {
    out->status = EpipolarRansacStatus::kInvalidInput;
    out->reason = fmt::format("{} bearings in the previous frame but {} in the current one",
                              f_C0.size(), f_C1.size());
    return false;
  }
  out->inlier.assign(f_C0.size(), false);
  return true;
}

EpipolarRansacResult TwoPointRansac(const std::vector<Eigen::Vector3d>& f_C0,
                                    const std::vector<Eigen::Vector3d>& f_C1,
                                    const Eigen::Matrix3d& R_C1_C0,
                                    const EpipolarRansacOptions& options) {
  EpipolarRansacResult out;
  out.R_C1_C0 = R_C1_C0;
  if (!StartEpipolarResult(f_C0, f_C1, &out)) return out;
  const double tau = options.threshold_rad;

  std::vector<TwoPointMatch> matches;
  matches.reserve(f_C0.size());
  for (size_t i = 0; i < f_C0.size(); ++i) {
    const double l0 = f_C0[i].norm(), l1 = f_C1[i].norm();
    if (!std::isfinite(l0) || !std::isfinite(l1) || !(l0 > 0.0) || !(l1 > 0.0)) continue;
    TwoPointMatch m;
    m.g = R_C1_C0 * (f_C0[i] / l0);
    m.f1 = f_C1[i] / l1;
    m.n = m.g.cross(m.f1);
    m.e_R = std::atan2(m.n.norm(), m.g.dot(m.f1)) / std::sqrt(2.0);
    m.index = i;
    matches.push_back(m);
  }
  const int count = static_cast<int>(matches.size());
  if (count < 2) {
    out.status = EpipolarRansacStatus::kTooFewMatches;
    out.reason = fmt::format("{} usable matches; the 2-point RANSAC needs at least 2", count);
    return out;
  }

  // Sampling (2), scoring (3)-(6), adaptive count (7).
  Rng rng(options.seed);
  TwoPointHypothesis best;
  int needed = std::max(1, options.max_iterations);
  int drawn = 0;
  for (; drawn < needed; ++drawn) {
    const int i = rng.UniformInt(0, count - 1);
    int j = rng.UniformInt(0, count - 2);
    if (j >= i) ++j;
    const Eigen::Vector3d& n1 = matches[i].n;
    const Eigen::Vector3d& n2 = matches[j].n;
    const Eigen::Vector3d t = n1.cross(n2);
    // No hypothesis from a match without parallax (n = 0) or from two matches on one epipolar
    // plane (n_1 parallel to n_2).
    const double n1n2 = n1.norm() * n2.norm();
    if (n1.norm() < 1e-12 || n2.norm() < 1e-12 || !(t.norm() > 1e-9 * n1n2)) continue;
    const TwoPointHypothesis h = TwoPointBestSign(matches, t.normalized(), tau);
    if (h.cost < best.cost) {
      best = h;
      needed = std::min(needed, std::max(std::min(options.min_iterations, options.max_iterations),
                                         RansacIterations(options.confidence,
                                                          static_cast<double>(best.inliers) / count,
                                                          2, options.max_iterations)));
    }
  }
  out.iterations = drawn;

  int parallax_matches = 0;
  for (const TwoPointMatch& m : matches) parallax_matches += m.e_R > tau ? 1 : 0;

  if (best.inliers == 0 && parallax_matches >= std::max(2, options.min_parallax_inliers)) {
    out.status = EpipolarRansacStatus::kDegenerate;
    out.reason = fmt::format(
        "{} matches have parallax but every sample's epipolar planes coincide (the normals "
        "(R f0) x f1 are parallel): the translation direction is not determined",
        parallax_matches);
    return out;
  }

  // Refit (8).
  best = TwoPointRefit(matches, best, tau, options.refine_rounds);

  // Pure rotation: too few of the translation's inliers need the translation.
  const int required_parallax =
      std::max(options.min_parallax_inliers,
               static_cast<int>(std::ceil(options.min_parallax_share * best.inliers)));
  if (best.parallax_inliers < required_parallax) {
    for (const TwoPointMatch& m : matches) {
      if (m.e_R > tau) continue;
      out.inlier[m.index] = true;
      ++out.num_inliers;
    }
    if (out.num_inliers == 0) {
      out.status = EpipolarRansacStatus::kNoConsensus;
      out.reason = fmt::format(
          "no match agrees with the rotation alone and no translation direction is supported "
          "by {} matches with parallax (best: {})",
          required_parallax, best.parallax_inliers);
      return out;
    }
    out.status = EpipolarRansacStatus::kPureRotation;
    out.reason = fmt::format(
        "no parallax: {} of {} matches agree with the rotation alone and the best translation "
        "direction is supported by {} matches with parallax (fewer than {}); the translation is "
        "zero or unobservable",
        out.num_inliers, count, best.parallax_inliers, required_parallax);
    out.direction_uncertainty_rad = std::numeric_limits<double>::infinity();
    return out;
  }

  // One common epipolar plane (9): the alternative t_perp, t turned by 90 deg about the dominant
  // normal N of the parallax inliers, must be rejected by enough of them.
  Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
  for (const TwoPointMatch& m : matches) {
    if (m.e_R <= tau) continue;
    bool inlier[2];
    double e2;
    TwoPointInlierOfSigns(m, best.t, tau, inlier, &e2);
    if (inlier[0]) normals += m.n * m.n.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> normal_eigen(normals);
  Eigen::Vector3d t_perp = normal_eigen.eigenvectors().col(2).cross(best.t);
  t_perp = t_perp.norm() > 1e-9 ? Eigen::Vector3d(t_perp.normalized()) : best.t.unitOrthogonal();
  int distinguishing = 0;
  for (const TwoPointMatch& m : matches) {
    if (m.e_R <= tau) continue;
    bool inlier[2];
    double e2;
    TwoPointInlierOfSigns(m, best.t, tau, inlier, &e2);
    if (!inlier[0]) continue;
    Eigen::Vector3d a, b;
    if (TwoPointSquaredError(m, t_perp, &a, &b) > tau * tau) ++distinguishing;
  }
  if (distinguishing < required_parallax) {
    out.status = EpipolarRansacStatus::kDegenerate;
    out.reason = fmt::format(
        "the translation direction is not determined: turned by 90 deg within the inliers' "
        "dominant epipolar plane it still explains all but {} of the {} inliers with parallax "
        "(fewer than {} reject it): their epipolar planes coincide",
        distinguishing, best.parallax_inliers, required_parallax);
    out.direction_uncertainty_rad = std::numeric_limits<double>::infinity();
    return out;
  }

  // Conditioning of the direction: the cost of turning t towards its weakest direction.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(TwoPointScatter(matches, best.t, tau),
                                                             Eigen::EigenvaluesOnly);
  const double curvature = eigen.eigenvalues()[1] - eigen.eigenvalues()[0];
  out.direction_uncertainty_rad =
      curvature > 0.0 ? 0.5 * tau / std::sqrt(curvature) : std::numeric_limits<double>::infinity();
  out.num_parallax_inliers = best.parallax_inliers;
  if (!(out.direction_uncertainty_rad <= options.max_direction_uncertainty_rad)) {
    out.status = EpipolarRansacStatus::kDegenerate;
    out.reason = fmt::format(
        "the {} inliers fix the translation direction only to within {:.1f} deg (more than "
        "max_direction_uncertainty_rad): their epipolar planes nearly coincide",
        best.inliers, out.direction_uncertainty_rad / kDeg);
    return out;
  }

  out.status = EpipolarRansacStatus::kOk;
  out.t_C1_C0 = best.t;
  out.inlier = TwoPointMask(matches, f_C0.size(), best.t, tau);
  out.num_inliers = best.inliers;
  return out;
}

}  // namespace mavloc
