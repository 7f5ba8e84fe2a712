#include "core/image_check.h"

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
#include <vector>

#include "core/input_limits.h"

namespace mavloc {

namespace {

std::string TooManyPixels(uint64_t width, uint64_t height) {
  return "image of " + std::to_string(width) + " x " + std::to_string(height) +
         " pixels is larger than " + std::to_string(input_limits::kMaxImagePixels) +
         " pixels (limit input_limits::kMaxImagePixels)";
}

// ---- PNG, through libpng with its error and warning handlers replaced. libpng leaves a failing
// call with longjmp: the functions that call setjmp hold no object with a destructor.

struct PngSource {
  const unsigned char* data = nullptr;
  size_t size = 0;
  size_t at = 0;
  char message[256] = {};
};

void PngRead(png_structp png, png_bytep out, png_size_t length) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (length > source->size - source->at) png_error(png, "Read Error (the file ends early)");
  std::memcpy(out, source->data + source->at, length);
  source->at += length;
}

void PngError(png_structp png, png_const_charp message) {
  auto* source = static_cast<PngSource*>(png_get_error_ptr(png));
  std::snprintf(source->message, sizeof source->message, "%s", message);
  png_longjmp(png, 1);
}

void PngWarning(png_structp /*png*/, png_const_charp /*message*/) {}

struct PngLayout {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  size_t row_bytes = 0;
  int passes = 1;
};

bool PngReadInfo(png_structp png, png_infop info, PngLayout* layout) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  layout->width = png_get_image_width(png, info);
  layout->height = png_get_image_height(png, info);
  layout->passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  layout->row_bytes = png_get_rowbytes(png, info);
  return true;
}

bool PngReadRows(png_structp png, png_infop info, const PngLayout* layout, png_bytep row) {
  if (setjmp(png_jmpbuf(png))) return false;
  for (int pass = 0; pass < layout->passes; ++pass) {
    for (png_uint_32 y = 0; y < layout->height; ++y) png_read_row(png, row, nullptr);
  }
  png_read_end(png, info);
  return true;
}

class PngDecoder {
 public:
  explicit PngDecoder(PngSource* source)
      : png_(png_create_read_struct(PNG_LIBPNG_VER_STRING, source, PngError, PngWarning)) {
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (info_ != nullptr) png_set_read_fn(png_, source, PngRead);
  }
  ~PngDecoder() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngDecoder(const PngDecoder&) = delete;
  PngDecoder& operator=(const PngDecoder&) = delete;

  std::string Damage(const PngSource& source) {
    if (info_ == nullptr) return "PNG: out of memory";
    PngLayout layout;
    if (!PngReadInfo(png_, info_, &layout)) return std::string("PNG: ") + source.message;
    if (uint64_t{layout.width} * layout.height > input_limits::kMaxImagePixels) {
      return "PNG: " + TooManyPixels(layout.width, layout.height);
    }
    std::vector<unsigned char> row(layout.row_bytes);
    if (!PngReadRows(png_, info_, &layout, row.data()))
      return std::string("PNG: ") + source.message;
    return "";
  }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

std::string PngDamage(const std::string& bytes) {
  PngSource source;
  source.data = reinterpret_cast<const unsigned char*>(bytes.data());
  source.size = bytes.size();
  PngDecoder decoder(&source);
  return decoder.Damage(source);
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

enum class JpegOutcome { kDecoded, kError, kTooLarge };

// Decodes at 1/8 scale: the entropy-coded data, where truncation and corruption show, is still
// read whole, but little of it is transformed back into pixels.
JpegOutcome JpegDecode(jpeg_decompress_struct* cinfo, JpegErrors* errors, const unsigned char* data,
                       unsigned long size) {
  if (setjmp(errors->jump)) return JpegOutcome::kError;
  jpeg_create_decompress(cinfo);
  jpeg_mem_src(cinfo, data, size);
  jpeg_read_header(cinfo, TRUE);
  if (uint64_t{cinfo->image_width} * cinfo->image_height > input_limits::kMaxImagePixels) {
    return JpegOutcome::kTooLarge;
  }
  cinfo->scale_num = 1;
  cinfo->scale_denom = 8;
  cinfo->dct_method = JDCT_IFAST;
  cinfo->do_fancy_upsampling = FALSE;
  jpeg_start_decompress(cinfo);
  JSAMPARRAY row = (*cinfo->mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(cinfo), JPOOL_IMAGE,
                                               cinfo->output_width * cinfo->output_components, 1);
  while (cinfo->output_scanline < cinfo->output_height) jpeg_read_scanlines(cinfo, row, 1);
  jpeg_finish_decompress(cinfo);
  return JpegOutcome::kDecoded;
}

std::string JpegDamage(const std::string& bytes) {
  jpeg_decompress_struct cinfo;
  std::memset(&cinfo, 0, sizeof cinfo);
  JpegErrors errors;
  std::memset(&errors, 0, sizeof errors);
  cinfo.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = JpegErrorExit;
  errors.manager.emit_message = JpegEmitMessage;
  errors.manager.output_message = JpegOutputMessage;
  const JpegOutcome outcome =
      JpegDecode(&cinfo, &errors, reinterpret_cast<const unsigned char*>(bytes.data()),
                 static_cast<unsigned long>(bytes.size()));
  const uint64_t width = cinfo.image_width, height = cinfo.image_height;
  jpeg_destroy_decompress(&cinfo);
  if (outcome == JpegOutcome::kTooLarge) return "JPEG: " + TooManyPixels(width, height);
  if (outcome == JpegOutcome::kError || errors.warned) {
    return std::string("JPEG: ") + errors.message;
  }
  return "";
}

bool StartsWith(const std::string& bytes, const char* magic, size_t size) {
  return bytes.size() >= size && std::memcmp(bytes.data(), magic, size) == 0;
}

}  // namespace

std::string ImageDamage(const std::string& bytes) {
  if (StartsWith(bytes, "\x89PNG\r\n\x1a\n", 8)) return PngDamage(bytes);
  if (StartsWith(bytes, "\xff\xd8\xff", 3)) return JpegDamage(bytes);
  return "";
}

}  // namespace mavloc
