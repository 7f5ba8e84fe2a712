// libFuzzer target for the calibration file reader (datasets/io/calibration_io.h): the input is
// one YAML file read as a lone EuRoC sensor.yaml of cam0 / Kalibr camchain, imu or target.yaml /
// yac config.yaml, whichever its content is.
#include <cstddef>
#include <cstdint>
#include <string>

#include "datasets/io/calibration_io.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mavloc::fuzz::WriteScratchFile("cam0/calibration.yaml", data, size);
  mavloc::fuzz::ExpectInputErrorOnly([&path] { (void)mavloc::ReadCalibrationSource(path); });
  return 0;
}
