// libFuzzer target for TagSLAM's cameras.yaml and camera_poses.yaml readers
// (datasets/io/tagslam/tagslam_cameras_io.h): the input is read as each of the two files, the
// other one absent.
#include <cstddef>
#include <cstdint>
#include <string>

#include "datasets/io/tagslam/tagslam_cameras_io.h"
#include "fuzz/fuzz_support.h"

namespace {

// TagSLAM test_1's cameras.yaml (berndpfrommer/tagslam_test).
constexpr char kCamerasYaml[] =
    "cam0:\n  camera_model: pinhole\n  intrinsics: [465.609, 465.632, 622.637, 513.902]\n"
    "  distortion_model: equidistant\n"
    "  distortion_coeffs: [-0.0229515, 0.01625, -0.00961832, 0.00176252]\n"
    "  resolution: [1280, 1024]\n  rostopic: /pg_16061245/image_raw\n"
    "  tagtopic: /pg_16061245/tags\n  rig_body: rig\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string fuzzed = mavloc::fuzz::WriteScratchFile("fuzzed.yaml", data, size);
  mavloc::fuzz::ExpectInputErrorOnly([&] { (void)mavloc::ReadTagslamCameras(fuzzed, ""); });
  static const std::string cameras = mavloc::fuzz::WriteScratchFile("cameras.yaml", kCamerasYaml);
  mavloc::fuzz::ExpectInputErrorOnly([&] { (void)mavloc::ReadTagslamCameras(cameras, fuzzed); });
  return 0;
}
