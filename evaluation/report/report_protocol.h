// The protocol of a report (report.h) from the trajectory-error engine's protocol
// (trajectory_evaluation.h).
#pragma once

#include "evaluation/report/report.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {

// by_index: the estimate was associated by index (KITTI poses without times).
ReportProtocol ReportProtocolOf(const EvaluationProtocol& protocol, bool by_index);

}  // namespace mavloc
