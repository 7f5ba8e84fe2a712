// The reference of a comparison on a log without ground truth (DESIGN.md "Evaluation": real logs
// rarely have ground truth): another estimator's output or a trajectory file the user names
// (`mavloc compare --reference ESTIMATOR|TRAJECTORY_FILE`). Differences to it are not errors:
// the reference is an estimate with errors of its own, and every report says so.
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"
#include "core/quantities.h"
#include "datasets/io/log_reader.h"

namespace mavloc {

struct ComparisonReference {
  enum class Kind { kEstimator, kTrajectoryFile, kLogTopic };
  Kind kind = Kind::kEstimator;
  std::string name;                // estimator name or file path
  QuantityTable quantities;        // compared per quantity (the names both provide)
  std::vector<StampedPose> poses;  // compared by ATE (T_W_B)

  // "estimator 'smoother'", "trajectory file 'path'" or "log topic 'file:topic'".
  std::string Describe() const;
};

// An estimator's output as the reference: all its quantities and poses.
ComparisonReference ReferenceFromEstimate(const std::string& estimator_name,
                                          const Estimate& estimate);
// A trajectory file (read by ReadTrajectoryFile) as the reference: x, y, z, roll, pitch, yaw (and
// vx, vy, vz when the file carries velocities, i.e. an EuRoC state CSV with non-zero v).
ComparisonReference ReferenceFromTrajectory(const std::string& path,
                                            const std::vector<GroundTruthState>& states);

// A trajectory topic of a ROS bag or ULog file as the reference (`--reference LOG:TOPIC`): only
// what its messages carry (vehicle_attitude: roll, pitch, yaw; vehicle_local_position: x, y, z and
// velocity); poses for the ATE only when they carry both position and attitude.
ComparisonReference ReferenceFromLogTrajectory(const std::string& spec,
                                               const LogTrajectory& trajectory);

}  // namespace mavloc
