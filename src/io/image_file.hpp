// Internal helper of src/io: reading an image file safely. The header is checked before the decoder
// (io/image_codec.hpp) runs, so a small file that declares a huge image is refused before it
// allocates gigabytes, and a JPEG or PNG cut short is refused instead of decoding to a partly grey
// image (libjpeg only prints "Premature end of JPEG file").
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "io/image_codec.hpp"

namespace zeroreg::detail {

// Largest image, in pixels, that is decoded: $ZEROREG_MAX_IMAGE_PIXELS when set (a number > 0),
// else 100 million (10000 x 10000; RGB-D cameras give at most a few million).
std::uint64_t MaxImagePixels();

// Most views one scan may hold (scan.json's "views", a Python scan's views):
// $ZEROREG_MAX_VIEWS when set (a number >= 1), else 64. Each view costs ~10 MiB while a scan is
// registered (images, depth, features, masks), so 64 views stay under 1 GiB; a scan is a handful
// of views in practice (3 for a 3DMatch fragment).
size_t MaxViewsPerScan();

// What the header of an in-memory image file says. `known` is false for formats other than PNG
// and JPEG, whose size is then checked after decoding.
struct ImageHeader {
  bool known = false;
  std::uint64_t width = 0, height = 0;
  bool complete = true;  // PNG: IEND chunk present; JPEG: end-of-image marker reached
  // JPEG: the segments do not chain up to the end-of-image marker (bytes where a marker belongs,
  // a length that is impossible or runs past an end-of-image marker that is there).
  bool corrupt = false;
  size_t corrupt_offset = 0;
  std::string format;  // "PNG", "JPEG" or ""
};
ImageHeader InspectImageHeader(const std::vector<std::uint8_t>& bytes);

// Reads `path` (a regular file; `what` names it in messages, e.g. "colour image"), checks the
// header (size within MaxImagePixels, file complete) and decodes it (DecodeImage, `mode`).
// Throws InputError naming the file. Returns an empty Mat when it is neither PNG nor JPEG.
cv::Mat ReadImageFile(const std::string& path, const std::string& what, ImageMode mode);

}  // namespace zeroreg::detail
