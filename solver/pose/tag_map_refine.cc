#include "solver/pose/tag_map_refine.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include "core/errors.h"
#include "core/tag_geometry.h"
#include "solver/smoother/residuals/pose_prior_factor.h"

namespace mavloc {

namespace {

// Corner c_T of a tag seen in one frame, in pixels (the cost of tag_map_refine.h):
//   p_C = R_B_C^T (R_W_B^T (R_W_T c_T + p_W_T - p_W_B) - p_B_C),   r = pi(p_C) - uv
// Parameter blocks: q_W_B (4, x y z w), p_W_B (3), q_W_T (4), p_W_T (3).
class RefineTagCornerResidual {
 public:
  RefineTagCornerResidual(const CameraModel& camera, const Pose& T_B_C, const Eigen::Vector3d& c_T,
                          const Eigen::Vector2d& uv_px)
      : camera_(camera), q_B_C_(T_B_C.q.normalized()), p_B_C_(T_B_C.p), c_T_(c_T), uv_px_(uv_px) {}

  template <typename T>
  bool operator()(const T* q_W_B_ptr, const T* p_W_B_ptr, const T* q_W_T_ptr, const T* p_W_T_ptr,
                  T* residuals) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Eigen::Quaternion<T>> q_W_B(q_W_B_ptr);
    const Eigen::Map<const Vec3> p_W_B(p_W_B_ptr);
    const Eigen::Map<const Eigen::Quaternion<T>> q_W_T(q_W_T_ptr);
    const Eigen::Map<const Vec3> p_W_T(p_W_T_ptr);
    const Vec3 p_W = q_W_T * c_T_.cast<T>() + p_W_T;
    const Vec3 p_B = q_W_B.conjugate() * (p_W - p_W_B);
    const Vec3 p_C = q_B_C_.cast<T>().conjugate() * (p_B - p_B_C_.cast<T>());
    if (!(p_C[2] > T(1e-6))) return false;
    T uv[2];
    camera_.ProjectT(p_C.data(), uv);
    residuals[0] = uv[0] - T(uv_px_[0]);
    residuals[1] = uv[1] - T(uv_px_[1]);
    return true;
  }

  static ceres::CostFunction* Create(const CameraModel& camera, const Pose& T_B_C,
                                     const Eigen::Vector3d& c_T, const Eigen::Vector2d& uv_px) {
    return new ceres::AutoDiffCostFunction<RefineTagCornerResidual, 2, 4, 3, 4, 3>(
        new RefineTagCornerResidual(camera, T_B_C, c_T, uv_px));
  }

 private:
  CameraModel camera_;
  Eigen::Quaterniond q_B_C_;
  Eigen::Vector3d p_B_C_;
  Eigen::Vector3d c_T_;
  Eigen::Vector2d uv_px_;
};

// One corner observation of the bundle adjustment.
struct RefineCorner {
  size_t frame = 0;  // index into the input frames
  int tag_id = 0;
  int k = 0;  // corner index (core/tag_geometry.h)
  Eigen::Vector2d uv_px;
};

// The unknowns, stored where Ceres can point at them (sizes fixed before the problem is built).
struct RefineState {
  std::vector<Eigen::Quaterniond> q_W_B;
  std::vector<Eigen::Vector3d> p_W_B;
  std::map<int, Eigen::Quaterniond> q_W_T;
  std::map<int, Eigen::Vector3d> p_W_T;
};

// Reprojection error of one corner under the state, in pixels (infinite behind the camera).
double RefineCornerError(const RefineCorner& c, const RefineState& s,
                         const std::map<int, TagInfo>& tags, const CameraSensor& camera) {
  const RefineTagCornerResidual residual(
      camera.model, camera.T_B_C, TagCornersInTagFrame(tags.at(c.tag_id).size_m)[c.k], c.uv_px);
  double r[2];
  if (!residual(s.q_W_B[c.frame].coeffs().data(), s.p_W_B[c.frame].data(),
                s.q_W_T.at(c.tag_id).coeffs().data(), s.p_W_T.at(c.tag_id).data(), r))
    return std::numeric_limits<double>::infinity();
  return std::hypot(r[0], r[1]);
}

double RefineRms(const std::vector<RefineCorner>& corners, const RefineState& s,
                 const std::map<int, TagInfo>& tags, const CameraSensor& camera) {
  double sum = 0.0;
  for (const RefineCorner& c : corners) {
    const double e = RefineCornerError(c, s, tags, camera);
    sum += e * e;
  }
  return corners.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(corners.size()));
}

// The frames that see at least min_tags map tags, their corners in front of the first camera
// pose, and the initial state (first frame poses, map tag poses).
std::vector<RefineCorner> CollectRefineCorners(const std::vector<TagMapRefineFrame>& frames,
                                               const std::map<int, TagInfo>& tags,
                                               const CameraSensor& camera, int min_tags,
                                               RefineState* state, int* frames_used) {
  std::vector<RefineCorner> corners;
  *frames_used = 0;
  for (size_t f = 0; f < frames.size(); ++f) {
    state->q_W_B.push_back(frames[f].T_W_B.q.normalized());
    state->p_W_B.push_back(frames[f].T_W_B.p);
    std::set<int> ids;
    for (const TagObservation& o : frames[f].observations)
      if (tags.count(o.tag_id)) ids.insert(o.tag_id);
    if (static_cast<int>(ids.size()) < min_tags) continue;
    ++*frames_used;
    for (const int id : ids) {
      state->q_W_T.emplace(id, tags.at(id).T_W_T.q.normalized());
      state->p_W_T.emplace(id, tags.at(id).T_W_T.p);
    }
    for (const TagObservation& o : frames[f].observations) {
      if (!ids.count(o.tag_id)) continue;
      for (int k = 0; k < 4; ++k) {
        RefineCorner c{f, o.tag_id, k, o.corners_px[k]};
        if (std::isfinite(RefineCornerError(c, *state, tags, camera))) corners.push_back(c);
      }
    }
  }
  return corners;
}

std::unique_ptr<ceres::LossFunction> MakeRefineLoss(TagMapRefineLoss loss, double scale_px) {
  if (loss == TagMapRefineLoss::kHuber) return std::make_unique<ceres::HuberLoss>(scale_px);
  return std::make_unique<ceres::CauchyLoss>(scale_px);
}

// The map prior of every tag: fixes the gauge (the map's W) and holds tags that no other tag
// constrains.
void AddRefineTagPriors(const std::map<int, TagInfo>& tags, const TagMapRefineOptions& options,
                        RefineState* s, ceres::Problem* problem) {
  Eigen::Matrix<double, 6, 1> sqrt_info;
  sqrt_info << Eigen::Vector3d::Constant(1.0 / options.tag_sigma_rad),
      Eigen::Vector3d::Constant(1.0 / options.tag_sigma_m);
  for (auto& [id, q_W_T] : s->q_W_T) {
    problem->AddResidualBlock(PosePriorFactor::Create(tags.at(id).T_W_T, sqrt_info.asDiagonal()),
                              nullptr, q_W_T.coeffs().data(), s->p_W_T.at(id).data());
    problem->SetManifold(q_W_T.coeffs().data(), new ceres::EigenQuaternionManifold);
  }
}

// Builds and solves the bundle adjustment over the corners; false when Ceres finds no usable
// solution (the state is then whatever Ceres left, the caller discards it).
bool SolveRefineProblem(const std::vector<RefineCorner>& corners,
                        const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                        const TagMapRefineOptions& options, double loss_scale_px, RefineState* s) {
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  const std::unique_ptr<ceres::LossFunction> loss = MakeRefineLoss(options.loss, loss_scale_px);
  for (const RefineCorner& c : corners) {
    problem.AddResidualBlock(RefineTagCornerResidual::Create(
                                 camera.model, camera.T_B_C,
                                 TagCornersInTagFrame(tags.at(c.tag_id).size_m)[c.k], c.uv_px),
                             loss.get(), s->q_W_B[c.frame].coeffs().data(),
                             s->p_W_B[c.frame].data(), s->q_W_T.at(c.tag_id).coeffs().data(),
                             s->p_W_T.at(c.tag_id).data());
  }
  for (Eigen::Quaterniond& q_W_B : s->q_W_B)
    if (problem.HasParameterBlock(q_W_B.coeffs().data()))
      problem.SetManifold(q_W_B.coeffs().data(), new ceres::EigenQuaternionManifold);
  AddRefineTagPriors(tags, options, s, &problem);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 2;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  return summary.IsSolutionUsable();
}

// Corners whose reprojection error is at most gate_px under the state.
std::vector<RefineCorner> GateRefineCorners(const std::vector<RefineCorner>& corners,
                                            const RefineState& s,
                                            const std::map<int, TagInfo>& tags,
                                            const CameraSensor& camera, double gate_px) {
  std::vector<RefineCorner> kept;
  for (const RefineCorner& c : corners)
    if (RefineCornerError(c, s, tags, camera) <= gate_px) kept.push_back(c);
  return kept;
}

double MedianRefineError(const std::vector<RefineCorner>& corners, const RefineState& s,
                         const std::map<int, TagInfo>& tags, const CameraSensor& camera) {
  std::vector<double> errors;
  for (const RefineCorner& c : corners) errors.push_back(RefineCornerError(c, s, tags, camera));
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

// Graduated robust loss (graduated non-convexity, Blake & Zisserman 1987; Black & Rangarajan,
// IJCV 1996): the scale starts at the corners' median error under the first poses and shrinks by
// a factor 4 per solve down to loss_scale_px, so that on a loose map (tens of pixels everywhere)
// the first steps do not take every corner for an outlier and stop in a local minimum.
bool SolveGraduated(const std::vector<RefineCorner>& corners, const std::map<int, TagInfo>& tags,
                    const CameraSensor& camera, const TagMapRefineOptions& options,
                    RefineState* s) {
  double scale_px = std::max(options.loss_scale_px, MedianRefineError(corners, *s, tags, camera));
  for (;;) {
    if (!SolveRefineProblem(corners, tags, camera, options, scale_px, s)) return false;
    if (scale_px <= options.loss_scale_px) return true;
    scale_px = std::max(options.loss_scale_px, scale_px / 4.0);
  }
}

TagMapRefinement RefineFailure(const std::vector<TagMapRefineFrame>& frames,
                               const std::map<int, TagInfo>& tags, std::string reason) {
  TagMapRefinement out;
  out.reason = std::move(reason);
  out.tags = tags;
  for (const TagMapRefineFrame& f : frames) out.T_W_B.push_back(f.T_W_B);
  return out;
}

// The refined map and frame poses of the state, with every refined tag's shift from the map.
void StoreRefinedState(const RefineState& s, TagMapRefinement* out) {
  for (size_t f = 0; f < s.q_W_B.size(); ++f)
    out->T_W_B.push_back(Pose(s.q_W_B[f].normalized(), s.p_W_B[f]));
  for (const auto& [id, q_W_T] : s.q_W_T) {
    TagInfo& tag = out->tags.at(id);
    const Pose T_W_T(q_W_T.normalized(), s.p_W_T.at(id));
    out->shifts.push_back(
        {id, (T_W_T.p - tag.T_W_T.p).norm(), RotationAngleBetween(T_W_T.q, tag.T_W_T.q)});
    tag.T_W_T = T_W_T;
  }
  std::sort(out->shifts.begin(), out->shifts.end(),
            [](const TagShift& a, const TagShift& b) { return a.shift_m > b.shift_m; });
}

}  // namespace

// The ranges (sigmas, loss scale, gate > 0) are checked when the estimator is created
// (solver/estimator_registry.cc, OptionRanges).
TagMapRefineOptions ParseTagMapRefineOptions(const EstimatorOptions& options) {
  TagMapRefineOptions out;
  const std::string mode = options.GetString("refine_map", "auto");
  if (mode == "auto") {
    out.mode = TagMapRefineMode::kAuto;
  } else if (mode == "1" || mode == "true") {
    out.mode = TagMapRefineMode::kOn;
  } else if (mode == "0" || mode == "false") {
    out.mode = TagMapRefineMode::kOff;
  } else {
    throw InputError("--option refine_map=" + mode + ": must be 0, 1 or auto");
  }
  out.tag_sigma_m = options.GetDouble("refine_sigma_m", out.tag_sigma_m);
  out.tag_sigma_rad = options.GetDouble("refine_sigma_rad", out.tag_sigma_rad);
  const std::string loss = options.GetString("refine_loss", "cauchy");
  if (loss != "huber" && loss != "cauchy")
    throw InputError("--option refine_loss=" + loss + ": must be huber or cauchy");
  out.loss = loss == "huber" ? TagMapRefineLoss::kHuber : TagMapRefineLoss::kCauchy;
  out.loss_scale_px = options.GetDouble("refine_loss_px", out.loss_scale_px);
  out.gate_px = options.GetDouble("refine_gate_px", out.gate_px);
  return out;
}

double TagMapRefinement::MaxShift_m() const {
  return shifts.empty() ? 0.0 : shifts.front().shift_m;
}

double TagMapRefinement::MedianShift_m() const {
  if (shifts.empty()) return 0.0;
  const size_t n = shifts.size();  // sorted, largest first
  return n % 2 ? shifts[n / 2].shift_m : 0.5 * (shifts[n / 2 - 1].shift_m + shifts[n / 2].shift_m);
}

std::string TagMapRefinement::Summary(int top) const {
  std::string text = fmt::format(
      "tag map refined over {} frames ({} corners, {} dropped at the gate; reprojection RMS {:.2f} "
      "-> {:.2f} px): the {} tags seen with another tag moved median {:.3f} m, max {:.3f} m",
      frames_used, corners_used, corners_dropped, rms_before_px, rms_after_px, shifts.size(),
      MedianShift_m(), MaxShift_m());
  for (int i = 0; i < top && i < static_cast<int>(shifts.size()); ++i)
    text += fmt::format("{}tag {} {:.3f} m {:.1f} deg", i == 0 ? " (most: " : ", ", shifts[i].id,
                        shifts[i].shift_m, shifts[i].angle_rad * 180.0 / M_PI);
  return text + (shifts.empty() ? "" : ")");
}

TagMapRefinement RefineTagMap(const std::vector<TagMapRefineFrame>& frames,
                              const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                              const TagMapRefineOptions& options) {
  RefineState state;
  int frames_used = 0;
  std::vector<RefineCorner> corners =
      CollectRefineCorners(frames, tags, camera, options.min_tags_per_frame, &state, &frames_used);
  if (corners.empty())
    return RefineFailure(frames, tags,
                         fmt::format("no frame sees {} map tags", options.min_tags_per_frame));
  const RefineState initial = state;
  if (!SolveGraduated(corners, tags, camera, options, &state))
    return RefineFailure(frames, tags, "the bundle adjustment found no usable solution");
  // Outliers: drop the corners beyond the gate, solve again from the first solution.
  const size_t before_gate = corners.size();
  corners = GateRefineCorners(corners, state, tags, camera, options.gate_px);
  if (corners.size() != before_gate && !corners.empty() &&
      !SolveRefineProblem(corners, tags, camera, options, options.loss_scale_px, &state))
    return RefineFailure(frames, tags, "the bundle adjustment found no usable solution");

  TagMapRefinement out;
  out.ok = true;
  out.tags = tags;
  out.frames_used = frames_used;
  out.corners_used = static_cast<int>(corners.size());
  out.corners_dropped = static_cast<int>(before_gate - corners.size());
  out.rms_before_px = RefineRms(corners, initial, tags, camera);
  out.rms_after_px = RefineRms(corners, state, tags, camera);
  StoreRefinedState(state, &out);
  return out;
}

}  // namespace mavloc
