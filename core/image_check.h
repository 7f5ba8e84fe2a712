// Checking an image file's bytes before OpenCV decodes them. libpng and libjpeg print their own
// errors and warnings to stderr ("libpng error: Read Error", "Premature end of JPEG file") when
// OpenCV hands them a damaged file, before mavloc reports the failure: two lines for one error,
// and a truncated JPEG even decodes to a half-grey image. Decoding the bytes here first, with
// handlers that collect the libraries' messages instead of printing them, lets a reader refuse a
// damaged image with one message of its own; an image that passes decodes in OpenCV without
// either library reporting an error.
#pragma once

#include <string>

namespace mavloc {

// Why `bytes` are not a complete, undamaged PNG or JPEG image ("PNG: Read Error", "JPEG:
// Premature end of JPEG file"), or "" when they decode cleanly or are of another format (left to
// OpenCV). An image of more than input_limits::kMaxImagePixels pixels is refused before it is
// decoded. A PNG's warnings (e.g. an ancillary chunk's CRC) do not count as damage, as in OpenCV;
// a JPEG's do (libjpeg warns about truncated or corrupt data and then fills the image in).
std::string ImageDamage(const std::string& bytes);

}  // namespace mavloc
