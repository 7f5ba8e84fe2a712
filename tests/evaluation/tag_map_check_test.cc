// The tag-map check of the per-frame PnP (solver/pose/tag_map_check.h): on random frames of the
// tag arena, a tag whose map pose is 0.25 m off is found from the frames where it is seen with
// other tags (while the frames where it is seen alone are 0.1 m or more off) and named; a correct
// map names no tag; map_check=0 checks nothing; tag-pnp reports the tag named as an event.
#include "solver/pose/tag_map_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "datasets/scenarios/scenario.h"
#include "datasets/scenarios/tag_arena.h"
#include "solver/estimator.h"

namespace mavloc {
namespace {

// Frames of a down-looking camera above the arena at random positions and headings, with the
// true tag poses; the body poses are returned alongside.
std::vector<std::vector<TagObservation>> RandomArenaFrames(int count, uint64_t seed,
                                                           std::vector<Pose>* T_W_B) {
  Rng rng(seed);
  const auto tags = TagArenaTags();
  const CameraSensor camera = TagArenaCamera(10.0);
  std::vector<std::vector<TagObservation>> frames;
  while (static_cast<int>(frames.size()) < count) {
    const Pose pose(
        QuaternionFromEuler(
            {rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1), rng.Uniform(-M_PI, M_PI)}),
        Eigen::Vector3d(rng.Uniform(0.5, 3.5), rng.Uniform(0.3, 1.1), rng.Uniform(1.2, 1.8)));
    auto observations = ProjectTagCorners(camera, pose, tags, 0, 0.3, rng);
    if (observations.empty()) continue;
    frames.push_back(std::move(observations));
    T_W_B->push_back(pose);
  }
  return frames;
}

int CountWithTag(const std::vector<std::vector<TagObservation>>& frames, int id, bool alone) {
  int n = 0;
  for (const auto& frame : frames) {
    bool seen = false;
    for (const auto& o : frame) seen = seen || o.tag_id == id;
    n += seen && (frame.size() == 1) == alone ? 1 : 0;
  }
  return n;
}

TEST(TagMapCheck, ATagWhoseMapPoseIsWrongIsLeftOutAndItsLoneFramesGetNoWrongPose) {
  std::vector<Pose> T_W_B;
  const auto frames = RandomArenaFrames(400, 31, &T_W_B);
  const CameraSensor camera = TagArenaCamera(10.0);
  // The tag most often seen, both alone and with others, is moved by 0.25 m in the map.
  int moved = -1, best = 0;
  for (const auto& [id, tag] : TagArenaTags()) {
    const int alone = CountWithTag(frames, id, true), with = CountWithTag(frames, id, false);
    if (alone >= 3 && with >= 5 && alone + with > best) moved = id, best = alone + with;
  }
  ASSERT_GE(moved, 0) << "no tag seen both alone and with others";
  auto map = TagArenaTags();
  map[moved].T_W_T.p += Eigen::Vector3d(0.2, -0.15, 0.0);

  const TagMapCheck check = CheckTagMap(frames, map, camera, {}, {});
  EXPECT_EQ(check.disagreeing, std::set<int>{moved});
  EXPECT_GE(check.counts.at(moved).disagree, 3);
  ASSERT_EQ(check.events.size(), 1u);
  EXPECT_NE(check.events[0].find("tag " + std::to_string(moved) + " disagrees with the map"),
            std::string::npos)
      << check.events[0];
  // What the check is for: the frames where the moved tag is seen alone are 0.1 m or more off,
  // and nothing in such a frame shows it.
  int lone = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].size() != 1 || frames[i][0].tag_id != moved) continue;
    ++lone;
    const CornerRansacResult wrong = CornerPnpRansac(frames[i], map, camera, {});
    ASSERT_TRUE(wrong.pnp.ok);
    EXPECT_GT((wrong.pnp.T_W_B.p - T_W_B[i].p).norm(), 0.1);
    EXPECT_LT(wrong.pnp.rms_reprojection_px, 1.0);
  }
  EXPECT_GE(lone, 3);
}

TEST(TagMapCheck, ACorrectMapKeepsEveryTagAndMapCheckOffChecksNothing) {
  std::vector<Pose> T_W_B;
  const auto frames = RandomArenaFrames(300, 32, &T_W_B);
  const CameraSensor camera = TagArenaCamera(10.0);
  const auto map = TagArenaTags();
  const TagMapCheck check = CheckTagMap(frames, map, camera, {}, {});
  EXPECT_TRUE(check.disagreeing.empty());
  EXPECT_TRUE(check.events.empty());
  EXPECT_GE(check.counts.size(), 10u);  // most tags were checked
  int disagreements = 0;
  for (const auto& [id, count] : check.counts) disagreements += count.disagree;
  EXPECT_EQ(disagreements, 0);

  TagMapCheckOptions off;
  off.enabled = false;
  auto moved = map;
  moved.begin()->second.T_W_T.p.x() += 0.5;
  const TagMapCheck none = CheckTagMap(frames, moved, camera, {}, off);
  EXPECT_TRUE(none.counts.empty());
  EXPECT_TRUE(none.disagreeing.empty());
}

TEST(TagMapCheck, TagPnpNamesTheMovedTagInItsEvents) {
  ScenarioOptions scenario;
  scenario.seed = 5;
  scenario.duration_s = 20.0;
  Dataset dataset = FindScenario("tag-arena-dynamic")->generate(scenario);
  std::map<int, int> seen;  // observations per tag
  for (const auto& o : dataset.tags) ++seen[o.tag_id];
  const int moved = std::max_element(seen.begin(), seen.end(), [](auto a, auto b) {
                      return a.second < b.second;
                    })->first;
  dataset.map.tags.at(moved).T_W_T.p += Eigen::Vector3d(0.2, -0.15, 0.0);
  const Estimate checked = FindEstimator("tag-pnp")->create(EstimatorOptions())->Run(dataset);
  // The check names the tag, and so the map is refined (refine_map=auto): that tag moved most.
  ASSERT_EQ(checked.events.size(), 2u);
  EXPECT_NE(checked.events[0].find("tag " + std::to_string(moved) + " disagrees"),
            std::string::npos)
      << checked.events[0];
  EXPECT_NE(checked.events[1].find("most: tag " + std::to_string(moved) + " "), std::string::npos)
      << checked.events[1];
  EstimatorOptions off;
  off.Set("map_check", "0");
  EXPECT_TRUE(FindEstimator("tag-pnp")->create(off)->Run(dataset).events.empty());
}

}  // namespace
}  // namespace mavloc
