// The report of `mavloc obstacles` in the one results model (evaluation/report/report.h): the
// settings and eq. (4)'s limits as its setup, the stage times in the form of the PIXHAWK paper's
// Table 1 (Meier et al. 2012, sec. 4), the alerts and, when the dataset describes its obstacles,
// precision, recall and the per-obstacle outcome; frames.csv and alerts.csv beside report.json.
// Times are seconds in report.json and milliseconds in report.md.
#pragma once

#include <optional>
#include <string>

#include "evaluation/obstacle_evaluation.h"
#include "evaluation/report/report.h"

namespace mavloc {

Report ObstacleReport(const std::string& dataset_name, const StereoObstacleRun& run,
                      const std::optional<ObstacleEvaluation>& evaluation);

}  // namespace mavloc
