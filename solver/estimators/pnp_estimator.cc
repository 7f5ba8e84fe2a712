#include "solver/estimators/pnp_estimator.h"

#include "solver/pixhawk/roll_pitch_source.h"
#include "solver/pose/corner_pnp.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

PnpEstimator::PnpEstimator(const EstimatorOptions& options)
    : image_delay_ms_(options.GetDouble("image_delay_ms", 0.0)),
      board_(ParseBoardInitOptions(options)) {}

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
  estimate.quantities = MakeQuantityTable(PoseQuantityNames(/*with_velocity=*/false));
  const CameraSensor& camera = *TagsCamera(dataset);
  const TimeNs delay_ns = SecondsToNs(1e-3 * image_delay_ms_);
  for (const TagFrame& frame : GroupTagFrames(dataset)) {
    if (frame.observations.empty()) {
      estimate.CountFailure("no marker in view");
      continue;
    }
    const CornerPnpResult result = CornerPnp(frame.observations, dataset.map.tags, camera);
    if (!result.ok) {
      estimate.CountFailure(result.reason);
      continue;
    }
    const TimeNs t = frame.t_ns - delay_ns;
    estimate.quantities.Append(t, PoseQuantityValues(result.T_W_B));
    estimate.poses.push_back({t, result.T_W_B});
  }
  return estimate;
}

}  // namespace mavloc
