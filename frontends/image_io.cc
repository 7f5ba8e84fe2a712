#include "frontends/image_io.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "core/errors.h"
#include "core/image_codec.h"

namespace mavloc {

cv::Mat LoadGrayImage(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, 0, "", "image file does not exist");
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw InputError(path, 0, "", "cannot read the image file");
  if (bytes.empty()) throw InputError(path, 0, "", "image file is empty");
  if (bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw InputError(path, 0, "", "image file is larger than 2 GB");
  std::string why;
  cv::Mat image = DecodeImage(bytes, ImageDecodeMode::kGray8, &why);
  if (image.empty()) throw InputError(path, 0, "", "cannot decode image: " + why);
  return image;
}

}  // namespace mavloc
