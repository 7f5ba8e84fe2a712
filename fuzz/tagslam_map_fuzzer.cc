// libFuzzer target for TagSLAM's tagslam.yaml reader (datasets/io/tagslam/tagslam_map_io.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "datasets/io/tagslam/tagslam_map_io.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mavloc::fuzz::WriteScratchFile("tagslam.yaml", data, size);
  mavloc::fuzz::ExpectInputErrorOnly([&path] { (void)mavloc::ReadTagslamMap(path); });
  return 0;
}
