// libFuzzer target for the trajectory file reader (datasets/io/trajectory_formats/
// trajectory_format.h): TUM, EuRoC, ASL-by-header and KITTI files, detected from the content as
// `--gt-format auto` does, read once refusing rows out of order and once sorting them.
#include <cstddef>
#include <cstdint>
#include <string>

#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mavloc::fuzz::WriteScratchFile("trajectory.txt", data, size);
  mavloc::fuzz::ExpectInputErrorOnly([&path] { (void)mavloc::ReadTrajectory(path); });
  mavloc::fuzz::ExpectInputErrorOnly([&path] {
    mavloc::TrajectoryReadOptions options;
    options.sort = true;
    const mavloc::LoadedTrajectory loaded = mavloc::ReadTrajectory(path, options);
    (void)mavloc::DescribeRowFixes(loaded.report);
  });
  return 0;
}
