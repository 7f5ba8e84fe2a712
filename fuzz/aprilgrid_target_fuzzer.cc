// libFuzzer target for the aprilgrid description reader (datasets/io/aprilgrid_target_io.h):
// Kalibr's target.yaml or yac's tag_rows/... keys.
#include <cstddef>
#include <cstdint>
#include <string>

#include "datasets/io/aprilgrid_target_io.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mavloc::fuzz::WriteScratchFile("target.yaml", data, size);
  mavloc::fuzz::ExpectInputErrorOnly([&path] { (void)mavloc::ReadAprilgridTarget(path); });
  return 0;
}
