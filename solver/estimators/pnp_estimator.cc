#include "solver/estimators/pnp_estimator.h"

#include "solver/pixhawk/roll_pitch_source.h"
#include "solver/pose/corner_pnp_ransac.h"
#include "solver/pose/tag_map_check.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

PnpEstimator::PnpEstimator(const EstimatorOptions& options)
    : image_delay_ms_(options.GetDouble("image_delay_ms", 0.0)),
      board_(ParseBoardInitOptions(options)),
      ransac_(ParseCornerRansacOptions(options)),
      map_check_(ParseTagMapCheckOptions(options)) {}

Applicability PnpEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.tags.empty()) return Applicability::No("needs tags0 corner observations");
  if (dataset.map.tags.empty()) return Applicability::No("needs tags (markers) in map.yaml");
  const std::string camera = TagsCameraMissing(dataset);
  if (!camera.empty()) return Applicability::No(camera);
  const std::string board = BoardWorldMissing(dataset);
  if (!board.empty()) return Applicability::No(board);
  return Applicability::Yes();
}

Estimate PnpEstimator::Run(const Dataset& dataset) {
  return RunInWorldFrame(dataset, board_, [&](const Dataset& dataset_W, const BoardWorld*) {
    return RunInWorld(dataset_W);
  });
}

Estimate PnpEstimator::RunInWorld(const Dataset& dataset) const {
  Estimate estimate;
  estimate.quantities = MakeQuantityTable(FramePoseQuantityNames());
  const CameraSensor& camera = *TagsCamera(dataset);
  const TimeNs delay_ns = SecondsToNs(1e-3 * image_delay_ms_);
  const std::vector<TagFrame> frames = GroupTagFrames(dataset);
  std::vector<std::vector<TagObservation>> observations;
  for (const TagFrame& frame : frames) observations.push_back(frame.observations);
  const TagMapCheck check =
      CheckTagMap(observations, dataset.map.tags, camera, ransac_, map_check_);
  estimate.events = check.events;
  for (const TagFrame& frame : frames) {
    if (frame.observations.empty()) {
      estimate.CountFailure("no marker in view");
      continue;
    }
    RecordFramePose(CornerPnpRansac(frame.observations, dataset.map.tags, camera, ransac_),
                    frame.t_ns - delay_ns, &estimate);
  }
  return estimate;
}

}  // namespace mavloc
