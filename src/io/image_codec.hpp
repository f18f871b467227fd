// Internal helper of src/io: PNG and JPEG decoding and encoding with libpng and libjpeg(-turbo)
// directly, not through OpenCV's imgcodecs. Why: libopencv_imgcodecs on Debian pulls in GDAL and
// about 120 further shared libraries whose symbol resolution and static initialisers cost every
// zeroreg process ~140 ms before main() (measured: an empty program linking imgcodecs starts in
// 167 ms, one linking only core + imgproc in 11 ms; docs/SPEED.md). The decoders give the same
// pixels as cv::imdecode for the files zeroreg reads (tested against it on the frames in
// ../shared/data: tests/io/image_codec_test.cpp).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace zeroreg::detail {

enum class ImageMode {
  // CV_8UC3, BGR, like cv::IMREAD_COLOR: grey replicated, alpha dropped, 16-bit samples reduced
  // to their high byte, palettes expanded. EXIF orientation is not applied: an RGB-D frame's
  // colour must stay registered with its depth image, which carries no orientation.
  kColor,
  // The samples as stored, like cv::IMREAD_UNCHANGED: 8 or 16 bits (sub-byte grey expanded to
  // 8), 1 channel for grey, 2 for grey + alpha, 3 (BGR) for colour and palettes, 4 (BGRA) with
  // alpha.
  kUnchanged,
};

// The format a file's first bytes announce: the PNG signature (8 bytes) or a JPEG start-of-image
// marker followed by another marker (FF D8 FF). Nothing past them is checked.
enum class ImageFormat { kUnknown, kPng, kJpeg };
ImageFormat SniffImageFormat(const std::vector<std::uint8_t>& bytes);

// Decodes a PNG or JPEG file held in memory. Returns an empty Mat when the bytes are neither
// format; throws std::runtime_error with libpng's / libjpeg's message when they are one of them
// but cannot be decoded.
cv::Mat DecodeImage(const std::vector<std::uint8_t>& bytes, ImageMode mode);

// PNG of an 8-bit (1, 3 = BGR or 4 = BGRA channels) or 16-bit single-channel image; JPEG
// (quality 1-100) of an 8-bit 1- or 3-channel (BGR) image. Throw std::invalid_argument for other
// types.
std::vector<std::uint8_t> EncodePng(const cv::Mat& image);
std::vector<std::uint8_t> EncodeJpeg(const cv::Mat& image, int quality);

// Writes `image` to `path` as PNG, or as JPEG (quality 95) when the name ends in .jpg / .jpeg.
// The file is replaced atomically (WriteFileAtomically: InputError with the system's reason when it
// cannot be written). Returns false when the image type cannot be encoded.
bool WriteImageFile(const std::string& path, const cv::Mat& image);

}  // namespace zeroreg::detail
