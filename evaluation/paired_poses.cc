#include "evaluation/paired_poses.h"

#include <limits>
#include <stdexcept>

namespace mavloc {

PairedPoses::PairedPoses(std::vector<PosePair> pairs) : whole_(std::move(pairs)) {}

PairedPoses::PairedPoses(const std::vector<StampedPose>& estimate,
                         const std::vector<StampedPose>& truth, TimeNs offset_ns, bool interpolate)
    : estimate_(&estimate), truth_(&truth), offset_ns_(offset_ns), interpolate_(interpolate) {
  constexpr size_t kMaxIndex = std::numeric_limits<uint32_t>::max();
  if (estimate.size() > kMaxIndex || truth.size() > kMaxIndex)
    throw std::length_error("PairedPoses: more than 2^32 - 1 poses in a trajectory");
}

void PairedPoses::Add(size_t e, size_t g) {
  estimate_index_.push_back(static_cast<uint32_t>(e));
  truth_index_.push_back(static_cast<uint32_t>(g));
}

void PairedPoses::Reserve(size_t n) {
  estimate_index_.reserve(n);
  truth_index_.reserve(n);
}

void PairedPoses::SetAlignment(const Similarity& S) {
  aligned_ = true;
  S_ = S;
  q_S_ = Eigen::Quaterniond(S.R);
}

TimeNs PairedPoses::t_ns(size_t i) const {
  return indexed() ? (*estimate_)[estimate_index_[i]].t_ns + offset_ns_ : whole_[i].t_ns;
}

double PairedPoses::InterpolationWeight(size_t i) const {
  const size_t g = truth_index_[i];
  const TimeNs t_low_ns = (*truth_)[g].t_ns, t = t_ns(i);
  if (!interpolate_ || t_low_ns == t) return 0.0;
  return static_cast<double>(t - t_low_ns) / static_cast<double>((*truth_)[g + 1].t_ns - t_low_ns);
}

Pose PairedPoses::TruthPose(size_t i) const {
  if (!indexed()) return whole_[i].T_W_B_gt;
  const size_t g = truth_index_[i];
  const double a = InterpolationWeight(i);
  if (a == 0.0) return (*truth_)[g].T_W_B;
  const Eigen::Quaterniond& q_low = (*truth_)[g].T_W_B.q;
  return Pose(q_low.slerp(a, (*truth_)[g + 1].T_W_B.q).normalized(), Lerp(g, a));
}

Eigen::Vector3d PairedPoses::p_gt(size_t i) const {
  if (!indexed()) return whole_[i].T_W_B_gt.p;
  const size_t g = truth_index_[i];
  const double a = InterpolationWeight(i);
  return a == 0.0 ? (*truth_)[g].T_W_B.p : Lerp(g, a);
}

Eigen::Vector3d PairedPoses::Lerp(size_t g, double a) const {
  return (1.0 - a) * (*truth_)[g].T_W_B.p + a * (*truth_)[g + 1].T_W_B.p;
}

Pose PairedPoses::MapEstimate(const Pose& T_W_B_est) const {
  if (!aligned_) return T_W_B_est;
  return ApplySimilarity(S_, q_S_, T_W_B_est);
}

PosePair PairedPoses::operator[](size_t i) const {
  if (!indexed()) {
    const PosePair& pair = whole_[i];
    return {pair.t_ns, MapEstimate(pair.T_W_B_est), pair.T_W_B_gt};
  }
  return {t_ns(i), MapEstimate((*estimate_)[estimate_index_[i]].T_W_B), TruthPose(i)};
}

}  // namespace mavloc
