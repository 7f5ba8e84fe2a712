// PIXHAWK marker localization timings: the known-vertical 2-point minimal solver (Kukelova et al.
// ACCV 2010; target < 100 ns per call), the least-squares refinement of x, y, z, yaw over 40
// corners, RANSAC + refinement, and the vision-only pnp on the same 40 corners (10 markers).
// Counters (PoseLib's solver benchmark): mean solutions per call and % of instances whose truth
// is among the solutions (error < 1e-8).
#include <benchmark/benchmark.h>

#include <vector>

#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "solver/pixhawk/upright_p2p.h"
#include "solver/pixhawk/upright_pose.h"
#include "solver/pose/corner_pnp.h"

namespace mavloc {
namespace {

struct P2pInstance {
  std::array<Eigen::Vector3d, 2> v_L, X_W;
  Eigen::Vector3d p_W;
  double yaw;
};

std::vector<P2pInstance> MakeP2pInstances(int count) {
  Rng rng(42);
  std::vector<P2pInstance> out(count);
  for (auto& inst : out) {
    inst.yaw = rng.Uniform(-M_PI, M_PI);
    inst.p_W = Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(0.5, 2.0)};
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d d =
          Eigen::Vector3d{rng.Uniform(-0.7, 0.7), rng.Uniform(-0.5, 0.5), -1.0}.normalized();
      inst.X_W[i] = inst.p_W + Rz(inst.yaw) * (rng.Uniform(0.5, 3.0) * d);
      inst.v_L[i] = d;
    }
  }
  return out;
}

void BM_UprightP2p(benchmark::State& state) {
  const auto instances = MakeP2pInstances(1024);
  std::vector<UprightPose> solutions;
  solutions.reserve(2);
  // Accuracy, outside the timed loop.
  long total = 0, found = 0;
  for (const auto& inst : instances) {
    total += upright_p2p(inst.v_L, inst.X_W, &solutions);
    for (const auto& s : solutions) {
      if ((s.p_W - inst.p_W).norm() < 1e-8 && std::abs(WrapAngle(s.yaw_rad() - inst.yaw)) < 1e-8) {
        ++found;
        break;
      }
    }
  }
  size_t k = 0;
  for (auto _ : state) {
    const auto& inst = instances[k];
    benchmark::DoNotOptimize(upright_p2p(inst.v_L, inst.X_W, &solutions));
    benchmark::DoNotOptimize(solutions.data());
    k = (k + 1) & 1023;
  }
  state.counters["solutions"] = static_cast<double>(total) / instances.size();
  state.counters["truth_found_%"] = 100.0 * found / instances.size();
}
BENCHMARK(BM_UprightP2p);

// 10 floor markers (40 corners) seen from 1.2 m by the down-looking camera, 1 px noise.
struct Scene {
  CameraSensor camera;
  std::map<int, TagInfo> tags;
  std::vector<TagObservation> observations;
  std::vector<Eigen::Vector3d> X_W;
  std::vector<Eigen::Vector2d> xy_C;
  EulerRpy rpy{0.03, -0.02, 0.4};
  Pose T_W_B;
};

Scene MakeScene() {
  Scene s;
  s.camera.T_B_C = Pose(Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()),
                        Eigen::Vector3d(0.03, 0.0, -0.05));
  s.camera.model = CameraModel(640, 480, Eigen::Vector4d(420, 420, 319.5, 239.5));
  s.T_W_B = Pose(RotationFromEuler(s.rpy), Eigen::Vector3d(0.1, -0.05, 1.2));
  const Pose T_C_W = (s.T_W_B * s.camera.T_B_C).Inverse();
  Rng rng(7);
  int id = 0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -1; j <= 0; ++j) {
      TagInfo tag;
      tag.id = id++;
      tag.size_m = 0.2;
      tag.T_W_T =
          Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.35 * i, 0.45 * j + 0.2, 0));
      s.tags[tag.id] = tag;
      TagObservation obs;
      obs.tag_id = tag.id;
      const auto corners = TagCornersInWorld(tag);
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector3d p_C = T_C_W * corners[c];
        const Eigen::Vector2d xy = p_C.head<2>() / p_C.z() + rng.GaussianVector<2>() / 420.0;
        obs.corners_px[c] = s.camera.model.NormalizedToPixel(xy);
        s.X_W.push_back(corners[c]);
        s.xy_C.push_back(xy);
      }
      s.observations.push_back(obs);
    }
  }
  return s;
}

void BM_UprightRefine40(benchmark::State& state) {
  const Scene s = MakeScene();
  const Eigen::Matrix3d R_L_C = LevelledCameraRotation(s.rpy.roll, s.rpy.pitch, s.camera.T_B_C.R());
  UprightPose initial;
  const double yaw0 = s.rpy.yaw + 0.02;
  initial.cos_yaw = std::cos(yaw0);
  initial.sin_yaw = std::sin(yaw0);
  initial.p_W = (s.T_W_B * s.camera.T_B_C).p + Eigen::Vector3d(0.03, -0.02, 0.02);
  int iterations = 0;
  for (auto _ : state) {
    const auto refined = RefineUprightPose(s.X_W, s.xy_C, R_L_C, 420.0, initial, 15);
    benchmark::DoNotOptimize(refined.pose.p_W.data());
    iterations = refined.iterations;
  }
  state.counters["corners"] = static_cast<double>(s.X_W.size());
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_UprightRefine40);

void BM_UprightRansacAndRefine40(benchmark::State& state) {
  const Scene s = MakeScene();
  for (auto _ : state) {
    const auto result =
        EstimateUprightPose(s.X_W, s.xy_C, s.rpy.roll, s.rpy.pitch, s.camera.T_B_C, 420.0);
    benchmark::DoNotOptimize(result.T_W_B.p.data());
  }
}
BENCHMARK(BM_UprightRansacAndRefine40);

void BM_CornerPnp40(benchmark::State& state) {
  const Scene s = MakeScene();
  for (auto _ : state) {
    const auto result = CornerPnp(s.observations, s.tags, s.camera);
    benchmark::DoNotOptimize(result.T_W_B.p.data());
  }
}
BENCHMARK(BM_CornerPnp40);

}  // namespace
}  // namespace mavloc
