#include "io/image_file.hpp"

#include <algorithm>
#include <fstream>

#include "io/file_bytes.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg::detail {
namespace {

constexpr double kDefaultMaxImagePixels = 100e6;
constexpr double kDefaultMaxViewsPerScan = 64;

std::uint32_t BigEndian32(const std::vector<std::uint8_t>& b, size_t i) {
  return (std::uint32_t{b[i]} << 24) | (std::uint32_t{b[i + 1]} << 16) |
         (std::uint32_t{b[i + 2]} << 8) | std::uint32_t{b[i + 3]};
}
unsigned BigEndian16(const std::vector<std::uint8_t>& b, size_t i) {
  return (unsigned{b[i]} << 8) | unsigned{b[i + 1]};
}

// PNG: the IHDR chunk comes first (width, height at bytes 16-23); the file ends with IEND.
ImageHeader InspectPng(const std::vector<std::uint8_t>& b) {
  ImageHeader h;
  h.format = "PNG";
  if (b.size() < 24) {
    h.complete = false;
    return h;
  }
  h.known = true;
  h.width = BigEndian32(b, 16);
  h.height = BigEndian32(b, 20);
  // The last chunk is IEND: length 0, "IEND", CRC (12 bytes). Allow a few bytes of trailing junk.
  const std::string tail(b.end() - static_cast<std::ptrdiff_t>(std::min<size_t>(b.size(), 64)),
                         b.end());
  h.complete = tail.find("IEND") != std::string::npos;
  return h;
}

bool IsStartOfFrame(unsigned marker) {
  // SOF0-SOF15 except DHT (C4), JPG (C8) and DAC (CC).
  return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

// JPEG: markers FF xx; segments carry a 2-byte length; after SOS comes entropy-coded data in which
// FF is always followed by 00 or a restart marker, until the next real marker. The file is complete
// when the end-of-image marker (FF D9) is reached.
ImageHeader InspectJpeg(const std::vector<std::uint8_t>& b) {
  ImageHeader h;
  h.format = "JPEG";
  h.complete = false;
  size_t i = 2;
  // A file that ends with the end-of-image marker but whose segments do not lead to it is
  // complete and corrupt, not truncated.
  const bool ends_with_eoi = b.size() >= 4 && b[b.size() - 2] == 0xFF && b[b.size() - 1] == 0xD9;
  const auto broken = [&](size_t at) {
    h.corrupt = true;
    h.corrupt_offset = at;
    return h;
  };
  while (i + 1 < b.size()) {
    if (b[i] != 0xFF) return broken(i);  // not at a marker
    const unsigned marker = b[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if (marker == 0xD9) {
      h.complete = true;
      return h;
    }
    if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {  // no length
      i += 2;
      continue;
    }
    if (i + 3 >= b.size()) return ends_with_eoi ? broken(i) : h;
    const size_t length = BigEndian16(b, i + 2);
    if (length < 2) return broken(i);  // a segment length counts its own two bytes
    if (IsStartOfFrame(marker) && i + 8 < b.size()) {
      h.known = true;
      h.height = BigEndian16(b, i + 5);
      h.width = BigEndian16(b, i + 7);
    }
    i += 2 + length;
    if (marker == 0xDA) {  // start of scan: skip the entropy-coded data
      while (i + 1 < b.size() &&
             !(b[i] == 0xFF && b[i + 1] != 0x00 && !(b[i + 1] >= 0xD0 && b[i + 1] <= 0xD7))) {
        ++i;
      }
    }
  }
  // Ran past the end: a segment's length pointed beyond the file.
  return ends_with_eoi ? broken(std::min(i, b.size())) : h;
}

}  // namespace

std::uint64_t MaxImagePixels() {
  return static_cast<std::uint64_t>(
      LimitFromEnvironment("ZEROREG_MAX_IMAGE_PIXELS", kDefaultMaxImagePixels));
}

size_t MaxViewsPerScan() {
  const double limit = LimitFromEnvironment("ZEROREG_MAX_VIEWS", kDefaultMaxViewsPerScan);
  return limit < 1 ? 1 : static_cast<size_t>(std::min(limit, 1e9));
}

ImageHeader InspectImageHeader(const std::vector<std::uint8_t>& bytes) {
  switch (SniffImageFormat(bytes)) {
    case ImageFormat::kPng:
      return InspectPng(bytes);
    case ImageFormat::kJpeg:
      return InspectJpeg(bytes);
    case ImageFormat::kUnknown:
      break;
  }
  return {};
}

cv::Mat ReadImageFile(const std::string& path, const std::string& what, ImageMode mode) {
  RequireFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MakeInputError(path, what + " cannot be opened for reading");
  const std::optional<std::vector<std::uint8_t>> read = ReadAllBytes<std::uint8_t>(in);
  if (!read) throw MakeInputError(path, what + " cannot be read");
  const std::vector<std::uint8_t>& bytes = *read;
  const ImageHeader header = InspectImageHeader(bytes);
  const std::uint64_t limit = MaxImagePixels();
  if (header.known && header.width * header.height > limit) {
    throw MakeInputError(path, what + " is " + std::to_string(header.width) + "x" +
                                   std::to_string(header.height) +
                                   " pixels, more than the limit of " + std::to_string(limit) +
                                   " pixels (set ZEROREG_MAX_IMAGE_PIXELS to raise it)");
  }
  if (header.corrupt) {
    throw MakeInputError(
        path, what + " is a corrupt " + header.format + " file (its structure is broken at byte " +
                  std::to_string(header.corrupt_offset) + " of " + std::to_string(bytes.size()) +
                  "); expected an image file that decodes");
  }
  if (!header.complete) {
    throw MakeInputError(path,
                         what + " is a truncated " + header.format + " file (" +
                             (header.format == "PNG" ? "no IEND chunk" : "no end-of-image marker") +
                             "); expected a complete image file");
  }
  cv::Mat image;
  try {
    image = DecodeImage(bytes, mode);
  } catch (const std::exception& e) {
    throw MakeInputError(path, what + " is corrupt and cannot be decoded (" + e.what() +
                                   "); expected an image file that decodes");
  }
  if (!image.empty() && static_cast<std::uint64_t>(image.total()) > limit) {
    throw MakeInputError(path, what + " has " + std::to_string(image.total()) +
                                   " pixels, more than the limit of " + std::to_string(limit) +
                                   " (set ZEROREG_MAX_IMAGE_PIXELS to raise it)");
  }
  return image;
}

}  // namespace zeroreg::detail
