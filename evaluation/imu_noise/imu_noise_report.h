// The report of `mavloc imu-noise` in the one results model (evaluation/report/report.h): one
// table per sensor (per axis and the sensor's value: white noise density, bias instability, random
// walk in SI units, each marked measured or an upper bound), the method and the Kalibr imu.yaml as
// a section, imu.yaml and allan_deviation.csv as the report's files.
#pragma once

#include <string>
#include <vector>

#include "evaluation/imu_noise/allan_deviation.h"
#include "evaluation/imu_noise/noise_fit.h"
#include "evaluation/report/report.h"

namespace mavloc {

struct ImuNoiseReportInput {
  std::string source;              // what was read (file, or LOG:TOPIC)
  std::string rostopic;            // imu.yaml's rostopic
  std::string window;              // "" or the --from/--to window in words
  std::vector<std::string> notes;  // the reader's notes
};

Report ImuNoiseReport(const ImuNoiseReportInput& input, const ImuNoiseFit& fit,
                      const ImuAllanDeviation& curves);

}  // namespace mavloc
