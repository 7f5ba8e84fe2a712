// libFuzzer target for yac's per-image aprilgrid corner files (datasets/io/aprilgrid_corners_io.h),
// read against EuRoC imu_april's grid (6 x 6 tags of 0.088 m, spacing 0.3) and the 752 x 480
// image of its cameras. The file is named after the `ts` of the first data row when it is a plain
// integer (so that inputs can get past the name check), else a fixed stamp.
#include <cstddef>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "datasets/io/aprilgrid_corners_io.h"
#include "fuzz/fuzz_support.h"

namespace {

std::string StampOfFirstRow(const std::string& text) {
  size_t begin = 0;
  while (begin < text.size() && text[begin] == '#') {
    const size_t end = text.find('\n', begin);
    if (end == std::string::npos) return {};
    begin = end + 1;
  }
  const size_t end = text.find(',', begin);
  if (end == std::string::npos || end == begin || end - begin > 19) return {};
  const std::string stamp = text.substr(begin, end - begin);
  if (stamp.find_first_not_of("0123456789") != std::string::npos) return {};
  return stamp;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string stamp = StampOfFirstRow(text);
  if (stamp.empty()) stamp = "1403709386537837056";
  const std::string path = mavloc::fuzz::WriteScratchFile("corners/" + stamp + ".csv", text);
  mavloc::AprilgridTarget target;
  target.tag_rows = 6;
  target.tag_cols = 6;
  target.tag_size_m = 0.088;
  target.tag_spacing = 0.3;
  mavloc::AprilgridCornerFileOptions options;
  options.image_size = Eigen::Vector2i(752, 480);
  mavloc::fuzz::ExpectInputErrorOnly(
      [&] { (void)mavloc::ReadAprilgridCornerFile(path, target, options); });
  return 0;
}
