// Vision-only pose from all visible marker corners (OpenCV IPPE / SQPnP + LM).
#include "solver/pose/corner_pnp.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"

namespace mavloc {
namespace {

CameraSensor DownLookingCamera() {
  CameraSensor camera;
  camera.name = "cam0";
  camera.T_B_C = Pose(Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()),
                      Eigen::Vector3d(0.05, 0.0, -0.03));
  camera.model = CameraModel(640, 480, Eigen::Vector4d(420, 420, 320, 240),
                             DistortionModel::kRadialTangential, {-0.1, 0.01, 0.0005, -0.0003});
  return camera;
}

std::map<int, TagInfo> FloorBoard() {
  std::map<int, TagInfo> tags;
  int id = 0;
  for (int i = -3; i <= 3; ++i) {
    for (int j = -3; j <= 3; ++j) {
      TagInfo tag;
      tag.id = id++;
      tag.size_m = 0.2;
      tag.T_W_T = Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.5 * i, 0.5 * j, 0.0));
      tags[tag.id] = tag;
    }
  }
  return tags;
}

// Observations of every tag fully in view, with Gaussian pixel noise.
std::vector<TagObservation> Observe(const Pose& T_W_B, const CameraSensor& camera,
                                    const std::map<int, TagInfo>& tags, double sigma_px, Rng& rng) {
  const Pose T_C_W = (T_W_B * camera.T_B_C).Inverse();
  std::vector<TagObservation> out;
  for (const auto& [id, tag] : tags) {
    TagObservation obs;
    obs.tag_id = id;
    bool visible = true;
    const auto corners = TagCornersInWorld(tag);
    for (int k = 0; k < 4 && visible; ++k) {
      const auto uv = camera.model.Project(T_C_W * corners[k]);
      visible = uv && camera.model.IsInside(*uv);
      if (visible) obs.corners_px[k] = *uv + sigma_px * rng.GaussianVector<2>();
    }
    if (visible) out.push_back(obs);
  }
  return out;
}

Pose RandomPose(Rng& rng) {
  return Pose{
      RotationFromEuler(
          {rng.Uniform(-0.15, 0.15), rng.Uniform(-0.15, 0.15), rng.Uniform(-M_PI, M_PI)}),
      Eigen::Vector3d{rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5), rng.Uniform(0.8, 1.6)}};
}

TEST(CornerPnpTest, NoiselessBoardGivesTheExactPose) {
  Rng rng(std::hash<std::string>{}("CornerPnpTest.Noiseless"));
  const CameraSensor camera = DownLookingCamera();
  const auto tags = FloorBoard();
  for (int n = 0; n < 30; ++n) {
    const Pose T_W_B = RandomPose(rng);
    const auto observations = Observe(T_W_B, camera, tags, 0.0, rng);
    ASSERT_GE(observations.size(), 2u);
    const auto result = CornerPnp(observations, tags, camera);
    ASSERT_TRUE(result.ok) << result.reason;
    EXPECT_EQ(result.num_corners, 4 * static_cast<int>(observations.size()));
    EXPECT_LT((result.T_W_B.p - T_W_B.p).norm(), 1e-6);
    EXPECT_LT(RotationAngleBetween(result.T_W_B.q, T_W_B.q), 1e-6);
    EXPECT_LT(result.rms_reprojection_px, 1e-4);
  }
}

TEST(CornerPnpTest, SingleTagAndNonCoplanarTags) {
  Rng rng(std::hash<std::string>{}("CornerPnpTest.SingleAndNonCoplanar"));
  const CameraSensor camera = DownLookingCamera();
  auto tags = FloorBoard();
  const Pose T_W_B(RotationFromEuler({0.05, -0.08, 0.4}), Eigen::Vector3d(0.1, 0.2, 1.2));
  auto observations = Observe(T_W_B, camera, tags, 0.0, rng);
  // One tag: IPPE on its 4 corners.
  const auto one = CornerPnp({observations.front()}, tags, camera);
  ASSERT_TRUE(one.ok) << one.reason;
  EXPECT_LT((one.T_W_B.p - T_W_B.p).norm(), 1e-6);
  EXPECT_FALSE(std::isnan(one.ambiguity_rms_px)) << one.ambiguity_rms_px;
  // Lift one tag 0.3 m off the floor and tilt it: corners are no longer coplanar (SQPnP).
  TagInfo& lifted = tags.at(24);  // the tag at the origin, below the camera
  lifted.T_W_T = Pose(Eigen::Quaterniond(Rx(0.3)), lifted.T_W_T.p + Eigen::Vector3d(0, 0, 0.3));
  observations = Observe(T_W_B, camera, tags, 0.0, rng);
  ASSERT_TRUE(std::any_of(observations.begin(), observations.end(),
                          [](const TagObservation& o) { return o.tag_id == 24; }));
  const auto mixed = CornerPnp(observations, tags, camera);
  ASSERT_TRUE(mixed.ok) << mixed.reason;
  EXPECT_LT((mixed.T_W_B.p - T_W_B.p).norm(), 1e-6);
  EXPECT_TRUE(std::isnan(mixed.ambiguity_rms_px));
}

TEST(CornerPnpTest, NoisyCornersGiveCentimetreAccuracy) {
  Rng rng(std::hash<std::string>{}("CornerPnpTest.Noisy"));
  const CameraSensor camera = DownLookingCamera();
  const auto tags = FloorBoard();
  double sum_sq = 0.0;
  for (int n = 0; n < 50; ++n) {
    const Pose T_W_B = RandomPose(rng);
    const auto result = CornerPnp(Observe(T_W_B, camera, tags, 1.0, rng), tags, camera);
    ASSERT_TRUE(result.ok) << result.reason;
    sum_sq += (result.T_W_B.p - T_W_B.p).squaredNorm();
    EXPECT_GT(result.rms_reprojection_px, 0.3);
    EXPECT_LT(result.rms_reprojection_px, 2.0);
  }
  EXPECT_LT(std::sqrt(sum_sq / 50), 0.03);
}

TEST(CornerPnpTest, TooFewCornersOrUnknownTagsFail) {
  const CameraSensor camera = DownLookingCamera();
  const auto tags = FloorBoard();
  TagObservation unknown{};
  unknown.tag_id = 999;
  const auto result = CornerPnp({unknown}, tags, camera);
  EXPECT_FALSE(result.ok);
  EXPECT_FALSE(result.reason.empty());
  EXPECT_FALSE(CornerPnp({}, tags, camera).ok);
  const auto three = CornerPnpFromCorrespondences(
      {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)},
      {Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 1), Eigen::Vector2d(1, 2)}, camera);
  EXPECT_FALSE(three.ok);
  EXPECT_EQ(three.reason, "fewer than 4 corners");
}

}  // namespace
}  // namespace mavloc
