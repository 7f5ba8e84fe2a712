// RANSAC over tag corners (solver/pose/corner_pnp_ransac.h): on random frames of the tag arena a
// tag with a misread id or a moved tag is found and left out, and the pose is as accurate as
// without the faulty tag, where the plain PnP on every corner is pulled away; two tags that
// disagree give no pose, with a reason; one tag alone is used (or refused with single_tag=0).
#include "solver/pose/corner_pnp_ransac.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "datasets/scenarios/tag_arena.h"

namespace mavloc {
namespace {

// A down-looking camera above the arena at a random position and heading.
Pose RandomBodyPose(Rng& rng) {
  const Eigen::Vector3d p(rng.Uniform(0.5, 3.5), rng.Uniform(0.3, 1.1), rng.Uniform(1.2, 1.8));
  return Pose(QuaternionFromEuler(
                  {rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1), rng.Uniform(-M_PI, M_PI)}),
              p);
}

double PositionError(const CornerPnpResult& r, const Pose& T_W_B) {
  return r.ok ? (r.T_W_B.p - T_W_B.p).norm() : INFINITY;
}

TEST(CornerPnpRansac, AMisreadIdOrAMovedTagIsLeftOut) {
  Rng rng(17);
  const auto tags = TagArenaTags();
  const CameraSensor camera = TagArenaCamera(10.0);
  int frames = 0;
  for (int trial = 0; trial < 200 && frames < 60; ++trial) {
    const Pose T_W_B = RandomBodyPose(rng);
    auto observations = ProjectTagCorners(camera, T_W_B, tags, 0, 0.3, rng);
    if (observations.size() < 3) continue;
    ++frames;
    // One tag is wrong: every other frame a misread id (another tag of the map), otherwise the
    // tag's corners shifted by 40 px (a moved tag).
    const size_t bad = static_cast<size_t>(trial) % observations.size();
    if (frames % 2 == 0) {
      observations[bad].tag_id = (observations[bad].tag_id + 7) % 21;
    } else {
      for (auto& corner : observations[bad].corners_px) corner += Eigen::Vector2d(40.0, -25.0);
    }
    const int bad_id = observations[bad].tag_id;
    const CornerRansacResult r = CornerPnpRansac(observations, tags, camera, {});
    ASSERT_TRUE(r.pnp.ok) << r.pnp.reason;
    ASSERT_EQ(r.outlier_tags.size(), 1u) << "frame " << frames;
    EXPECT_EQ(r.outlier_tags[0], bad_id);
    EXPECT_EQ(r.inlier_tags.size(), observations.size() - 1);
    // The same pose as the plain PnP on the frame without the faulty tag.
    auto clean = observations;
    clean.erase(clean.begin() + static_cast<long>(bad));
    const CornerPnpResult without = CornerPnp(clean, tags, camera);
    ASSERT_TRUE(without.ok);
    EXPECT_LT((r.pnp.T_W_B.p - without.T_W_B.p).norm(), 1e-6);
    // The same frame without RANSAC: pulled away by the faulty tag.
    CornerRansacOptions off;
    off.enabled = false;
    const CornerRansacResult all = CornerPnpRansac(observations, tags, camera, off);
    EXPECT_GT(PositionError(all.pnp, T_W_B), 2.0 * PositionError(r.pnp, T_W_B));
  }
  EXPECT_GE(frames, 40);
}

TEST(CornerPnpRansac, CleanFramesKeepEveryTagAndMatchThePlainPnp) {
  Rng rng(18);
  const auto tags = TagArenaTags();
  const CameraSensor camera = TagArenaCamera(10.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose T_W_B = RandomBodyPose(rng);
    const auto observations = ProjectTagCorners(camera, T_W_B, tags, 0, 0.3, rng);
    if (observations.size() < 2) continue;
    const CornerRansacResult r = CornerPnpRansac(observations, tags, camera, {});
    ASSERT_TRUE(r.pnp.ok);
    EXPECT_TRUE(r.outlier_tags.empty());
    const CornerPnpResult plain = CornerPnp(observations, tags, camera);
    EXPECT_LT((r.pnp.T_W_B.p - plain.T_W_B.p).norm(), 1e-9);
  }
}

TEST(CornerPnpRansac, TwoDisagreeingTagsGiveNoPoseAndOneTagIsUsedAsItIs) {
  Rng rng(19);
  const auto tags = TagArenaTags();
  const CameraSensor camera = TagArenaCamera(10.0);
  std::vector<TagObservation> observations;
  Pose T_W_B;
  while (observations.size() < 2) {
    T_W_B = RandomBodyPose(rng);
    observations = ProjectTagCorners(camera, T_W_B, tags, 0, 0.3, rng);
  }
  observations.resize(2);
  for (auto& corner : observations[1].corners_px) corner += Eigen::Vector2d(30.0, 30.0);
  const CornerRansacResult r = CornerPnpRansac(observations, tags, camera, {});
  EXPECT_FALSE(r.pnp.ok);
  EXPECT_NE(r.pnp.reason.find("agree"), std::string::npos) << r.pnp.reason;

  observations.resize(1);
  EXPECT_TRUE(CornerPnpRansac(observations, tags, camera, {}).pnp.ok);
  CornerRansacOptions strict;
  strict.single_tag = false;
  const CornerRansacResult refused = CornerPnpRansac(observations, tags, camera, strict);
  EXPECT_FALSE(refused.pnp.ok);
  EXPECT_NE(refused.pnp.reason.find("single_tag=0"), std::string::npos);
  // No tag of the map.
  observations[0].tag_id = 999;
  EXPECT_FALSE(CornerPnpRansac(observations, tags, camera, {}).pnp.ok);
}

}  // namespace
}  // namespace mavloc
