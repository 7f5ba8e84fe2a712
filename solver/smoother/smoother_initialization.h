// Initial keyframe states for the smoother from a seed estimator's output (the closed-form and
// PnP estimators: three-point, upright-2p, pnp, tag-pnp, laser-ekf):
// - poses: the seed's T_W_B at the keyframe time (its poses, or its x y z roll pitch yaw);
// - velocities: central finite differences of the seed positions of the neighbouring seeded
//   keyframes (one-sided at the ends);
// - biases: zero;
// - keyframes where the seed failed (no pose, or a pose further than gate_m from the IMU
//   prediction) are bridged by IMU prediction (RK4 strapdown, solver/imu/imu_integrator.h) from the
//   previous keyframe; keyframes before the first seeded one by backward prediction from it
//   (BridgeBackwards).
#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"
#include "solver/smoother/smoother_problem.h"

namespace mavloc {

struct SmootherInitialization {
  std::vector<SmootherKeyframe> keyframes;
  std::vector<bool> seeded;             // per keyframe: from the seed (true) or bridged (false)
  std::map<std::string, int> failures;  // by reason
};

// Keyframe times: the cam0 frame times and the times of visual measurements (features0, tags0,
// tags1, laser0) that lie inside the IMU stream, sorted and unique; every stride-th one is kept.
std::vector<TimeNs> SmootherKeyframeTimes(const Dataset& dataset, int stride = 1);

// The seed's poses as stamped T_W_B: Estimate::poses, or else the quantities x y z roll pitch yaw.
std::vector<StampedPose> SeedPoses(const Estimate& seed);

struct SmootherInitializationOptions {
  double match_tolerance_s = 0.002;  // a seed pose belongs to a keyframe within this time
  double gate_m = 1.0;               // seeds further than this from the IMU prediction are rejected
  double max_difference_window_s = 1.0;  // neighbours used for finite differences
};

// Prepends the keyframes of keyframe_times before init's first keyframe, each predicted backwards
// by the IMU (zero biases) from the one after it; counted as failures "keyframe before the first
// seed pose (bridged backwards)". No-op when init has no keyframe.
void BridgeBackwards(const Dataset& dataset, const std::vector<TimeNs>& keyframe_times,
                     SmootherInitialization* init);

SmootherInitialization InitializeFromSeed(const Dataset& dataset,
                                          const std::vector<TimeNs>& keyframe_times,
                                          const std::vector<StampedPose>& seed_poses,
                                          const SmootherInitializationOptions& options = {});

// Positions of unknown features from the initial keyframes: each observed bearing is intersected
// with the ground plane z = 0 (on_ground) and the intersections averaged; otherwise the
// least-squares intersection of the rays (needs two non-parallel rays). Features with no valid
// ray are left out.
std::map<int, Eigen::Vector3d> TriangulateFeatures(const Dataset& dataset,
                                                   const std::vector<SmootherKeyframe>& keyframes,
                                                   bool on_ground);

}  // namespace mavloc

namespace mavloc {

// The plane of the laser spots from the initial keyframes: each spot is triangulated as the point
// of the laser beam closest to the camera ray of its observation (baseline = the beam's offset from
// the camera centre), and a plane is fitted to the spots (total least squares). The normal points
// towards the first keyframe's camera. nullopt with fewer than 3 spots or collinear ones.
std::optional<Plane> FitLaserPlane(const Dataset& dataset,
                                   const std::vector<SmootherKeyframe>& keyframes,
                                   const LaserBeam& beam);

}  // namespace mavloc

namespace mavloc {

// A seed for features0 with known landmarks (no registry estimator covers them): per frame, the
// PnP of solver/pose/corner_pnp.h on the observed landmarks (>= 4 per frame), with the normalized
// coordinates mapped to ideal pinhole pixels. Frames with fewer landmarks or a failed PnP give no
// pose (counted in *failures when given).
std::vector<StampedPose> LandmarkPnpSeed(const Dataset& dataset,
                                         std::map<std::string, int>* failures = nullptr);

// A seed from one camera's tags (camera_index 0: tags0, 1: tags1) with that camera's calibration:
// per frame, CornerPnp of solver/pose/corner_pnp.h on all its map tags (tag-pnp reads tags0 only;
// this covers cam1-only data). Poses are in the map's frame (W, or the board frame M on a board
// map). Frames without a pose are counted in *failures when given.
std::vector<StampedPose> TagPnpSeed(const Dataset& dataset, int camera_index,
                                    std::map<std::string, int>* failures = nullptr);

}  // namespace mavloc

namespace mavloc {

// Laser-only data (Martinelli & Troiani, RR-7906): the laser EKF gives only the observable modes
// d, v_o, roll, pitch (of C relative to the plane frame P) and alpha. The keyframes are placed in a
// gauge frame W' in which the plane passes through the origin with normal n = Rx(alpha) e_z
// (returned in *gauge_plane); the unobservable in-plane position and velocity start at zero and
// follow the IMU; the yaw of C about the normal comes from the gravity direction of the
// accelerometer averaged over +-0.5 s (well defined when alpha is not small).
SmootherInitialization InitializeFromLaserModes(const Dataset& dataset,
                                                const std::vector<TimeNs>& keyframe_times,
                                                const QuantityTable& modes, Plane* gauge_plane);

}  // namespace mavloc
