// PNG and JPEG images in and out, through libpng and libjpeg directly (not OpenCV's imgcodecs,
// whose GDAL, GDCM, HDF5 and Poppler dependencies made every mavloc process load about 120 more
// shared libraries at start-up).
//
// Decoding gives the pixels OpenCV's cv::imdecode gives for the same flags: gray from colour with
// libpng's rgb_to_gray (0.299, 0.587) or libjpeg's own grayscale output, 16-bit samples stripped to
// their high byte for gray, colour as BGR. Both libraries' error and warning handlers are replaced:
// a damaged file is refused with the library's reason ("PNG: Read Error", "JPEG: Premature end of
// JPEG file") and nothing is printed, and a truncated JPEG is not filled in with grey. A PNG's
// warnings (an ancillary chunk's CRC) are not damage, as in OpenCV; a JPEG's are (libjpeg warns
// about truncated or corrupt data and then fills the image in). An image of more than
// input_limits::kMaxImagePixels pixels is refused from its header, before it is decoded.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace mavloc {

enum class ImageDecodeMode {
  kGray8,      // CV_8UC1 (cv::IMREAD_GRAYSCALE)
  kUnchanged,  // the file's depth (8 or 16 bit) and channels: gray, BGR or BGRA
};

// The image in `bytes` (a PNG or JPEG file's contents). On failure returns an empty Mat and sets
// *why ("PNG: Read Error", "not a PNG or JPEG file (mavloc reads PNG and JPEG images)").
cv::Mat DecodeImage(const std::string& bytes, ImageDecodeMode mode, std::string* why);

// A PNG file's contents for an 8- or 16-bit image of 1 (gray), 3 (BGR) or 4 (BGRA) channels;
// throws std::invalid_argument for any other type.
std::string EncodePng(const cv::Mat& image);

}  // namespace mavloc
