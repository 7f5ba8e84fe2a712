#include "core/image_codec.h"

// jpeglib.h needs FILE and size_t declared first.
#include <cstddef>
#include <cstdio>
// clang-format off
#include <jpeglib.h>
// clang-format on
#include <png.h>

#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/input_limits.h"

namespace mavloc {

namespace {

std::string TooManyPixels(uint64_t width, uint64_t height) {
  return "image of " + std::to_string(width) + " x " + std::to_string(height) +
         " pixels is larger than " + std::to_string(input_limits::kMaxImagePixels) +
         " pixels (limit input_limits::kMaxImagePixels)";
}

bool LittleEndian() {
  const uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// ---- PNG, through libpng with its error and warning handlers replaced. libpng leaves a failing
// call with longjmp: the functions that call setjmp hold no object with a destructor.

struct PngIo {
  const unsigned char* data = nullptr;  // reading
  size_t size = 0;
  size_t at = 0;
  std::string* out = nullptr;  // writing
  char message[256] = {};
};

void PngReadBytes(png_structp png, png_bytep out, png_size_t length) {
  auto* io = static_cast<PngIo*>(png_get_io_ptr(png));
  if (length > io->size - io->at) png_error(png, "Read Error (the file ends early)");
  std::memcpy(out, io->data + io->at, length);
  io->at += length;
}

void PngWriteBytes(png_structp png, png_bytep data, png_size_t length) {
  static_cast<PngIo*>(png_get_io_ptr(png))
      ->out->append(reinterpret_cast<const char*>(data), length);
}

void PngFlush(png_structp /*png*/) {}

void PngError(png_structp png, png_const_charp message) {
  auto* io = static_cast<PngIo*>(png_get_error_ptr(png));
  std::snprintf(io->message, sizeof io->message, "%s", message);
  png_longjmp(png, 1);
}

void PngWarning(png_structp /*png*/, png_const_charp /*message*/) {}

struct PngLayout {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int channels = 0;  // after the transforms
  int bit_depth = 0;
};

bool PngReadHeader(png_structp png, png_infop info, PngLayout* layout) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  layout->width = png_get_image_width(png, info);
  layout->height = png_get_image_height(png, info);
  return true;
}

// The transforms of OpenCV's PNG decoder for IMREAD_GRAYSCALE and IMREAD_UNCHANGED.
bool PngSetTransforms(png_structp png, png_infop info, ImageDecodeMode mode, PngLayout* layout) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int color_type = png_get_color_type(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  const bool has_trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((color_type & PNG_COLOR_MASK_COLOR) == 0 && bit_depth < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  if (mode == ImageDecodeMode::kGray8) {
    if (bit_depth == 16) png_set_strip_16(png);
    png_set_strip_alpha(png);
    if (color_type & PNG_COLOR_MASK_COLOR) png_set_rgb_to_gray(png, 1, 0.299, 0.587);
  } else {
    if (bit_depth == 16 && LittleEndian()) png_set_swap(png);
    const bool alpha = (color_type & PNG_COLOR_MASK_ALPHA) != 0 || has_trns;
    if (has_trns) png_set_tRNS_to_alpha(png);
    if (alpha && (color_type & PNG_COLOR_MASK_COLOR) == 0) png_set_gray_to_rgb(png);
    if (alpha || (color_type & PNG_COLOR_MASK_COLOR)) png_set_bgr(png);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  layout->channels = png_get_channels(png, info);
  layout->bit_depth = png_get_bit_depth(png, info);
  return true;
}

bool PngReadPixels(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

class PngReader {
 public:
  explicit PngReader(PngIo* io)
      : png_(png_create_read_struct(PNG_LIBPNG_VER_STRING, io, PngError, PngWarning)) {
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (info_ != nullptr) png_set_read_fn(png_, io, PngReadBytes);
  }
  ~PngReader() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  cv::Mat Decode(const PngIo& io, ImageDecodeMode mode, std::string* why) {
    const auto fail = [&](const std::string& reason) {
      *why = "PNG: " + reason;
      return cv::Mat();
    };
    if (info_ == nullptr) return fail("out of memory");
    PngLayout layout;
    if (!PngReadHeader(png_, info_, &layout)) return fail(io.message);
    if (uint64_t{layout.width} * layout.height > input_limits::kMaxImagePixels)
      return fail(TooManyPixels(layout.width, layout.height));
    if (!PngSetTransforms(png_, info_, mode, &layout)) return fail(io.message);
    if (layout.channels < 1 || layout.channels > 4 || layout.channels == 2 ||
        (layout.bit_depth != 8 && layout.bit_depth != 16))
      return fail("unsupported layout after conversion");
    const int depth = layout.bit_depth == 16 ? CV_16U : CV_8U;
    cv::Mat image(static_cast<int>(layout.height), static_cast<int>(layout.width),
                  CV_MAKETYPE(depth, layout.channels));
    std::vector<png_bytep> rows(layout.height);
    for (png_uint_32 y = 0; y < layout.height; ++y)
      rows[y] = image.ptr<png_byte>(static_cast<int>(y));
    if (!PngReadPixels(png_, info_, rows.data())) return fail(io.message);
    return image;
  }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

cv::Mat DecodePng(const std::string& bytes, ImageDecodeMode mode, std::string* why) {
  PngIo io;
  io.data = reinterpret_cast<const unsigned char*>(bytes.data());
  io.size = bytes.size();
  PngReader reader(&io);
  return reader.Decode(io, mode, why);
}

bool PngWriteAll(png_structp png, png_infop info, const cv::Mat& image, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int channels = image.channels();
  const int color_type = channels == 1   ? PNG_COLOR_TYPE_GRAY
                         : channels == 3 ? PNG_COLOR_TYPE_RGB
                                         : PNG_COLOR_TYPE_RGB_ALPHA;
  const int bit_depth = image.depth() == CV_16U ? 16 : 8;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols),
               static_cast<png_uint_32>(image.rows), bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 1);  // OpenCV's default: fast, the images are re-read, not kept
  png_write_info(png, info);
  if (channels > 1) png_set_bgr(png);
  if (bit_depth == 16 && LittleEndian()) png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

// ---- JPEG, through libjpeg with an error manager that keeps the first warning and leaves a
// failing call with longjmp instead of printing.

struct JpegErrors {
  jpeg_error_mgr manager;  // first: libjpeg hands its handlers a pointer to it
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  bool warned;
};

void JpegErrorExit(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, errors->message);
  std::longjmp(errors->jump, 1);
}

// level < 0: a warning (truncated or corrupt data); above: trace messages.
void JpegEmitMessage(j_common_ptr cinfo, int level) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  if (level >= 0 || errors->warned) return;
  (*cinfo->err->format_message)(cinfo, errors->message);
  errors->warned = true;
}

void JpegOutputMessage(j_common_ptr /*cinfo*/) {}

bool JpegReadHeader(jpeg_decompress_struct* cinfo, JpegErrors* errors, const unsigned char* data,
                    unsigned long size) {
  if (setjmp(errors->jump)) return false;
  jpeg_create_decompress(cinfo);
  jpeg_mem_src(cinfo, data, size);
  jpeg_read_header(cinfo, TRUE);
  return true;
}

// OpenCV's JPEG decoder: libjpeg's grayscale output for gray, BGR for colour.
bool JpegStart(jpeg_decompress_struct* cinfo, JpegErrors* errors, bool gray) {
  if (setjmp(errors->jump)) return false;
  cinfo->out_color_space = gray ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_start_decompress(cinfo);
  return true;
}

bool JpegReadRows(jpeg_decompress_struct* cinfo, JpegErrors* errors, cv::Mat* image) {
  if (setjmp(errors->jump)) return false;
  while (cinfo->output_scanline < cinfo->output_height) {
    JSAMPROW row = image->ptr<JSAMPLE>(static_cast<int>(cinfo->output_scanline));
    jpeg_read_scanlines(cinfo, &row, 1);
  }
  jpeg_finish_decompress(cinfo);
  return true;
}

cv::Mat JpegDecodeWith(jpeg_decompress_struct* cinfo, JpegErrors* errors, const std::string& bytes,
                       ImageDecodeMode mode, std::string* why) {
  const auto fail = [&](const std::string& reason) {
    *why = "JPEG: " + reason;
    return cv::Mat();
  };
  if (!JpegReadHeader(cinfo, errors, reinterpret_cast<const unsigned char*>(bytes.data()),
                      static_cast<unsigned long>(bytes.size())))
    return fail(errors->message);
  if (uint64_t{cinfo->image_width} * cinfo->image_height > input_limits::kMaxImagePixels)
    return fail(TooManyPixels(cinfo->image_width, cinfo->image_height));
  if (cinfo->num_components != 1 && cinfo->num_components != 3)
    return fail("a JPEG of " + std::to_string(cinfo->num_components) +
                " components (CMYK) is not supported; gray and colour JPEGs are");
  const bool gray = mode == ImageDecodeMode::kGray8 || cinfo->num_components == 1;
  if (!JpegStart(cinfo, errors, gray)) return fail(errors->message);
  cv::Mat image(static_cast<int>(cinfo->output_height), static_cast<int>(cinfo->output_width),
                gray ? CV_8UC1 : CV_8UC3);
  if (!JpegReadRows(cinfo, errors, &image) || errors->warned) return fail(errors->message);
  return image;
}

cv::Mat DecodeJpeg(const std::string& bytes, ImageDecodeMode mode, std::string* why) {
  jpeg_decompress_struct cinfo;
  std::memset(&cinfo, 0, sizeof cinfo);
  JpegErrors errors;
  std::memset(&errors, 0, sizeof errors);
  cinfo.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = JpegErrorExit;
  errors.manager.emit_message = JpegEmitMessage;
  errors.manager.output_message = JpegOutputMessage;
  cv::Mat image = JpegDecodeWith(&cinfo, &errors, bytes, mode, why);
  jpeg_destroy_decompress(&cinfo);
  return image;
}

bool StartsWith(const std::string& bytes, const char* magic, size_t size) {
  return bytes.size() >= size && std::memcmp(bytes.data(), magic, size) == 0;
}

}  // namespace

cv::Mat DecodeImage(const std::string& bytes, ImageDecodeMode mode, std::string* why) {
  why->clear();
  if (StartsWith(bytes, "\x89PNG\r\n\x1a\n", 8)) return DecodePng(bytes, mode, why);
  if (StartsWith(bytes, "\xff\xd8\xff", 3)) return DecodeJpeg(bytes, mode, why);
  *why = bytes.empty() ? "empty image file"
                       : "not a PNG or JPEG file (mavloc reads PNG and JPEG images)";
  return cv::Mat();
}

std::string EncodePng(const cv::Mat& image) {
  const int channels = image.channels();
  if (image.empty() || (image.depth() != CV_8U && image.depth() != CV_16U) ||
      (channels != 1 && channels != 3 && channels != 4))
    throw std::invalid_argument("EncodePng: an 8- or 16-bit image of 1, 3 or 4 channels is needed");
  std::string out;
  PngIo io;
  io.out = &out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &io, PngError, PngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  bool ok = info != nullptr;
  if (ok) {
    png_set_write_fn(png, &io, PngWriteBytes, PngFlush);
    std::vector<png_bytep> rows(static_cast<size_t>(image.rows));
    for (int y = 0; y < image.rows; ++y)
      rows[static_cast<size_t>(y)] = const_cast<png_bytep>(image.ptr<png_byte>(y));
    ok = PngWriteAll(png, info, image, rows.data());
  }
  png_destroy_write_struct(&png, &info);
  if (!ok) throw std::runtime_error(std::string("PNG encoding failed: ") + io.message);
  return out;
}

}  // namespace mavloc
