// Loading camera images on demand (DESIGN.md: cam0 images are loaded when a frontend needs them).
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace mavloc {

// Loads a greyscale 8-bit image; throws InputError naming the file when it is missing,
// unreadable or damaged. A damaged PNG or JPEG gives that one message: the codec libraries' own
// output is never printed (core/image_check.h).
cv::Mat LoadGrayImage(const std::string& path);

}  // namespace mavloc
