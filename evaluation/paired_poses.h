// The associated pose pairs of a trajectory evaluation (association.h), held as two indices per
// pair into the estimate and the ground truth (8 bytes a pair instead of two copied poses and a
// stamp, 120 bytes: a 500,000-pose estimate keeps 4 MB instead of 60 MB). A pair is formed when
// it is read, with the association's arithmetic:
// - t_ns = estimate stamp + time offset (truth time);
// - the truth pose: nearest mode, truth[g] as it is; interpolated mode, truth[g] when its stamp
//   equals t_ns, else between truth[g] and truth[g + 1] at a = (t - t_g) / (t_(g+1) - t_g):
//   p = (1 - a) p_g + a p_(g+1), q = slerp(q_g, q_(g+1), a) normalized;
// - the estimate pose, mapped by the alignment S once one is set (SetAlignment):
//   T_est' = (q_S q_est, s R_S p_est + t_S), as ApplySimilarity (alignment.h).
// Reading a pair twice gives the same bits. Pairs can also be given whole (tests, small callers);
// the alignment then applies to them the same way.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#include "core/pose.h"
#include "evaluation/alignment.h"

namespace mavloc {

struct PosePair {
  TimeNs t_ns = 0;
  Pose T_W_B_est;
  Pose T_W_B_gt;
};

class PairedPoses {
 public:
  PairedPoses() = default;
  // Pairs given whole. Implicit, so that a std::vector<PosePair> passes where pairs are read.
  PairedPoses(std::vector<PosePair> pairs);  // NOLINT(google-explicit-constructor)
  // Pairs by index into estimate and truth, which must outlive this object; stamps of the
  // estimate are shifted by offset_ns. interpolate: the truth is interpolated between g and g + 1
  // (interpolated association), else truth[g] is taken as it is (nearest).
  PairedPoses(const std::vector<StampedPose>& estimate, const std::vector<StampedPose>& truth,
              TimeNs offset_ns, bool interpolate);

  // Appends the pair (estimate[e], truth[g]) (index form only).
  void Add(size_t e, size_t g);
  void Reserve(size_t n);

  // Every pair read from now on carries the estimate mapped by S.
  void SetAlignment(const Similarity& S);

  size_t size() const { return indexed() ? estimate_index_.size() : whole_.size(); }
  bool empty() const { return size() == 0; }
  PosePair operator[](size_t i) const;
  PosePair front() const { return (*this)[0]; }
  PosePair back() const { return (*this)[size() - 1]; }
  TimeNs t_ns(size_t i) const;
  // Index form: the estimate pose and the (lower) truth pose of pair i.
  size_t estimate_index(size_t i) const { return estimate_index_[i]; }
  size_t truth_index(size_t i) const { return truth_index_[i]; }
  // The truth position of pair i alone (the same bits as (*this)[i].T_W_B_gt.p, without the
  // slerp).
  Eigen::Vector3d p_gt(size_t i) const;

  // Input iterator over the pairs (each formed as it is read).
  class Iterator {
   public:
    using iterator_category = std::input_iterator_tag;
    using value_type = PosePair;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = PosePair;
    Iterator(const PairedPoses* pairs, size_t i) : pairs_(pairs), i_(i) {}
    PosePair operator*() const { return (*pairs_)[i_]; }
    Iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator==(const Iterator& other) const { return i_ == other.i_; }
    bool operator!=(const Iterator& other) const { return i_ != other.i_; }

   private:
    const PairedPoses* pairs_;
    size_t i_;
  };
  Iterator begin() const { return Iterator(this, 0); }
  Iterator end() const { return Iterator(this, size()); }

 private:
  bool indexed() const { return estimate_ != nullptr; }
  Pose TruthPose(size_t i) const;
  // Interpolated mode: the truth's lower node of pair i and the weight of the upper one (0 when
  // the stamps are equal).
  double InterpolationWeight(size_t i) const;
  // (1 - a) p_g + a p_(g+1) of the truth.
  Eigen::Vector3d Lerp(size_t g, double a) const;
  Pose MapEstimate(const Pose& T_W_B_est) const;

  std::vector<PosePair> whole_;
  const std::vector<StampedPose>* estimate_ = nullptr;
  const std::vector<StampedPose>* truth_ = nullptr;
  TimeNs offset_ns_ = 0;
  bool interpolate_ = false;
  std::vector<uint32_t> estimate_index_;
  std::vector<uint32_t> truth_index_;
  bool aligned_ = false;
  Similarity S_;
  Eigen::Quaterniond q_S_ = Eigen::Quaterniond::Identity();
};

}  // namespace mavloc
