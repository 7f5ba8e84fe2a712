#include "frontends/image_io.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "core/errors.h"
#include "core/image_check.h"

namespace mavloc {

cv::Mat LoadGrayImage(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, 0, "", "image file does not exist");
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw InputError(path, 0, "", "cannot read the image file");
  if (bytes.empty()) throw InputError(path, 0, "", "image file is empty");
  if (bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw InputError(path, 0, "", "image file is larger than 2 GB");
  // A damaged PNG or JPEG is refused here, with the codec's reason, before OpenCV would hand it
  // to libpng / libjpeg, which print their own line (core/image_check.h).
  const std::string damage = ImageDamage(bytes);
  if (!damage.empty()) throw InputError(path, 0, "", "cannot decode image: " + damage);
  const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8UC1,
                        const_cast<char*>(bytes.data()));
  cv::Mat image = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw InputError(path, 0, "", "cannot decode image");
  return image;
}

}  // namespace mavloc
