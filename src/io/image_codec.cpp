#include "io/image_codec.hpp"

// libjpeg's header needs size_t and FILE declared first.
#include <cstdio>
#include <cstring>
// clang-format off
#include <jpeglib.h>
// clang-format on
#include <png.h>

#include <algorithm>
#include <cctype>
#include <csetjmp>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "io/text_parsing.hpp"

namespace zeroreg::detail {
namespace {

// Both libraries report fatal errors by calling back into the application, which must not
// return: the callbacks below longjmp to the setjmp of the function that started the work. To
// keep that well defined, every object those functions change after setjmp lives in a state
// struct owned by the caller (reached through a pointer that never changes), and no C++ object
// with a destructor is created between setjmp and the last library call.

// ---- PNG ---------------------------------------------------------------------------------------

struct PngDecodeState {
  const std::vector<std::uint8_t>* bytes = nullptr;
  size_t position = 0;
  ImageMode mode = ImageMode::kColor;
  std::string error;
  cv::Mat image;
  std::vector<png_bytep> rows;
};

void PngError(png_structp png, png_const_charp message) {
  *static_cast<std::string*>(png_get_error_ptr(png)) = message ? message : "unknown error";
  png_longjmp(png, 1);
}
void PngWarning(png_structp, png_const_charp) {}  // warnings (e.g. unknown chunks) are not errors

void PngReadFromMemory(png_structp png, png_bytep out, png_size_t count) {
  auto* state = static_cast<PngDecodeState*>(png_get_io_ptr(png));
  if (state->position + count > state->bytes->size()) png_error(png, "unexpected end of file");
  std::memcpy(out, state->bytes->data() + state->position, count);
  state->position += count;
}

bool RunPngDecode(png_structp png, png_infop info, PngDecodeState* state) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_read_fn(png, state, PngReadFromMemory);
  png_read_info(png, info);
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
  png_get_IHDR(png, info, &width, &height, &bit_depth, &color_type, nullptr, nullptr, nullptr);
  const bool colour = (color_type & PNG_COLOR_MASK_COLOR) != 0;  // palettes included
  const bool transparency = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  bool alpha = (color_type & PNG_COLOR_MASK_ALPHA) != 0;
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (!colour && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  int channels = 0, depth = CV_8U;
  if (state->mode == ImageMode::kColor) {
    if (bit_depth == 16) png_set_strip_16(png);
    if (alpha) png_set_strip_alpha(png);
    if (!colour) png_set_gray_to_rgb(png);
    png_set_bgr(png);
    channels = 3;
  } else {
    if (transparency) {
      png_set_tRNS_to_alpha(png);
      alpha = true;
    }
    if (bit_depth == 16) {
      png_set_swap(png);  // PNG stores 16-bit samples big-endian; the host is little-endian
      depth = CV_16U;
    }
    if (colour) png_set_bgr(png);
    channels = (colour ? 3 : 1) + (alpha ? 1 : 0);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const size_t sample_bytes = depth == CV_16U ? 2 : 1;
  if (png_get_rowbytes(png, info) != size_t{width} * channels * sample_bytes) {
    png_error(png, "unexpected row layout after conversion");
  }
  state->image.create(static_cast<int>(height), static_cast<int>(width),
                      CV_MAKETYPE(depth, channels));
  state->rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) state->rows[y] = state->image.ptr(static_cast<int>(y));
  png_read_image(png, state->rows.data());
  return true;
}

cv::Mat DecodePng(const std::vector<std::uint8_t>& bytes, ImageMode mode) {
  PngDecodeState state;
  state.bytes = &bytes;
  state.mode = mode;
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &state.error, PngError, PngWarning);
  if (!png) throw std::runtime_error("libpng: out of memory");
  png_infop info = png_create_info_struct(png);
  const bool ok = info && RunPngDecode(png, info, &state);
  png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
  if (!ok)
    throw std::runtime_error("PNG: " + (state.error.empty() ? "out of memory" : state.error));
  return state.image;
}

struct PngEncodeState {
  const cv::Mat* image = nullptr;
  std::string error;
  std::vector<std::uint8_t> out;
  std::vector<png_bytep> rows;
};

void PngWriteToMemory(png_structp png, png_bytep data, png_size_t count) {
  auto* state = static_cast<PngEncodeState*>(png_get_io_ptr(png));
  state->out.insert(state->out.end(), data, data + count);
}
void PngFlush(png_structp) {}

bool RunPngEncode(png_structp png, png_infop info, PngEncodeState* state) {
  if (setjmp(png_jmpbuf(png))) return false;
  const cv::Mat& image = *state->image;
  png_set_write_fn(png, state, PngWriteToMemory, PngFlush);
  // zlib level 3: pictures and fused frames are written often and read rarely; levels above
  // ~3 shrink such images by a few percent at several times the time.
  png_set_compression_level(png, 3);
  const int channels = image.channels();
  const int color_type = channels == 1   ? PNG_COLOR_TYPE_GRAY
                         : channels == 3 ? PNG_COLOR_TYPE_RGB
                                         : PNG_COLOR_TYPE_RGB_ALPHA;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols),
               static_cast<png_uint_32>(image.rows), image.depth() == CV_16U ? 16 : 8, color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (channels >= 3) png_set_bgr(png);
  if (image.depth() == CV_16U) png_set_swap(png);
  state->rows.resize(static_cast<size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) state->rows[y] = const_cast<png_bytep>(image.ptr(y));
  png_write_image(png, state->rows.data());
  png_write_end(png, nullptr);
  return true;
}

// ---- JPEG --------------------------------------------------------------------------------------

struct JpegErrorManager {
  jpeg_error_mgr base;  // first member: libjpeg sees a jpeg_error_mgr*
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

void JpegErrorExit(j_common_ptr info) {
  auto* manager = reinterpret_cast<JpegErrorManager*>(info->err);
  (*info->err->format_message)(info, manager->message);
  std::longjmp(manager->jump, 1);
}
// Warnings (e.g. "Premature end of JPEG file") are not printed: InspectImageHeader refuses
// truncated files before decoding, and a library should not write to stderr.
void JpegSilence(j_common_ptr) {}

// The error manager for a (de)compressor: libjpeg's defaults, with the two callbacks above.
jpeg_error_mgr* JpegErrors(JpegErrorManager* manager) {
  jpeg_error_mgr* errors = jpeg_std_error(&manager->base);
  errors->error_exit = JpegErrorExit;
  errors->output_message = JpegSilence;
  return errors;
}

struct JpegDecodeState {
  const std::vector<std::uint8_t>* bytes = nullptr;
  jpeg_decompress_struct info;
  JpegErrorManager errors;
  cv::Mat image;
  bool unsupported_cmyk = false;
};

bool RunJpegDecode(JpegDecodeState* state) {
  jpeg_decompress_struct& info = state->info;
  if (setjmp(state->errors.jump)) return false;
  jpeg_mem_src(&info, state->bytes->data(), static_cast<unsigned long>(state->bytes->size()));
  jpeg_read_header(&info, TRUE);
  if (info.num_components != 1 && info.num_components != 3) {
    state->unsupported_cmyk = true;
    return false;
  }
  const bool grey = info.num_components == 1;
  // libjpeg-turbo converts YCbCr straight to BGR (as OpenCV's decoder asks it to).
  info.out_color_space = grey ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_start_decompress(&info);
  const int channels = static_cast<int>(info.output_components);
  state->image.create(static_cast<int>(info.output_height), static_cast<int>(info.output_width),
                      CV_MAKETYPE(CV_8U, channels));
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = state->image.ptr(static_cast<int>(info.output_scanline));
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  return true;
}

cv::Mat DecodeJpeg(const std::vector<std::uint8_t>& bytes, ImageMode mode) {
  JpegDecodeState state;
  state.bytes = &bytes;
  state.info.err = JpegErrors(&state.errors);
  jpeg_create_decompress(&state.info);
  const bool ok = RunJpegDecode(&state);
  jpeg_destroy_decompress(&state.info);
  if (state.unsupported_cmyk) {
    throw std::runtime_error("JPEG: CMYK / YCCK colour (4 components) is not supported");
  }
  if (!ok) throw std::runtime_error(std::string("JPEG: ") + state.errors.message);
  if (mode == ImageMode::kColor && state.image.channels() == 1) {
    cv::Mat bgr(state.image.size(), CV_8UC3);
    cv::Mat planes[] = {state.image, state.image, state.image};
    cv::merge(planes, 3, bgr);
    return bgr;
  }
  return state.image;
}

struct JpegEncodeState {
  const cv::Mat* image = nullptr;
  int quality = 95;
  jpeg_compress_struct info;
  JpegErrorManager errors;
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
};

bool RunJpegEncode(JpegEncodeState* state) {
  jpeg_compress_struct& info = state->info;
  const cv::Mat& image = *state->image;
  if (setjmp(state->errors.jump)) return false;
  jpeg_mem_dest(&info, &state->buffer, &state->size);
  info.image_width = static_cast<JDIMENSION>(image.cols);
  info.image_height = static_cast<JDIMENSION>(image.rows);
  info.input_components = image.channels();
  info.in_color_space = image.channels() == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, state->quality, TRUE);
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(image.ptr(static_cast<int>(info.next_scanline)));
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  return true;
}

}  // namespace

ImageFormat SniffImageFormat(const std::vector<std::uint8_t>& bytes) {
  static const std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (bytes.size() >= 8 && std::equal(kPng, kPng + 8, bytes.begin())) return ImageFormat::kPng;
  if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) {
    return ImageFormat::kJpeg;
  }
  return ImageFormat::kUnknown;
}

cv::Mat DecodeImage(const std::vector<std::uint8_t>& bytes, ImageMode mode) {
  switch (SniffImageFormat(bytes)) {
    case ImageFormat::kPng:
      return DecodePng(bytes, mode);
    case ImageFormat::kJpeg:
      return DecodeJpeg(bytes, mode);
    case ImageFormat::kUnknown:
      break;
  }
  return {};
}

std::vector<std::uint8_t> EncodePng(const cv::Mat& image) {
  const bool eight_bit = image.depth() == CV_8U &&
                         (image.channels() == 1 || image.channels() == 3 || image.channels() == 4);
  if (image.empty() || !(eight_bit || image.type() == CV_16UC1)) {
    throw std::invalid_argument(
        "EncodePng: expected a non-empty 8-bit 1-, 3- or 4-channel or 16-bit 1-channel image");
  }
  PngEncodeState state;
  state.image = &image;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &state.error, PngError, PngWarning);
  if (!png) throw std::runtime_error("libpng: out of memory");
  png_infop info = png_create_info_struct(png);
  const bool ok = info && RunPngEncode(png, info, &state);
  png_destroy_write_struct(&png, info ? &info : nullptr);
  if (!ok)
    throw std::runtime_error("PNG: " + (state.error.empty() ? "out of memory" : state.error));
  return std::move(state.out);
}

std::vector<std::uint8_t> EncodeJpeg(const cv::Mat& image, int quality) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::invalid_argument("EncodeJpeg: expected a non-empty 8-bit 1- or 3-channel image");
  }
  JpegEncodeState state;
  state.image = &image;
  state.quality = std::clamp(quality, 1, 100);
  state.info.err = JpegErrors(&state.errors);
  jpeg_create_compress(&state.info);
  const bool ok = RunJpegEncode(&state);
  jpeg_destroy_compress(&state.info);
  std::vector<std::uint8_t> out;
  if (ok && state.buffer) out.assign(state.buffer, state.buffer + state.size);
  std::free(state.buffer);  // jpeg_mem_dest allocates with malloc
  if (!ok) throw std::runtime_error(std::string("JPEG: ") + state.errors.message);
  return out;
}

bool WriteImageFile(const std::string& path, const cv::Mat& image) {
  std::string extension = path.substr(std::min(path.size(), path.find_last_of('.')));
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::vector<std::uint8_t> bytes;
  try {
    bytes =
        (extension == ".jpg" || extension == ".jpeg") ? EncodeJpeg(image, 95) : EncodePng(image);
  } catch (const std::exception&) {
    return false;
  }
  // Through a temporary file and a rename: a full disk leaves the previous picture, not half of
  // the new one, and the InputError says why.
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
  return true;
}

}  // namespace zeroreg::detail
