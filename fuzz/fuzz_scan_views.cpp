// libFuzzer harness for a scan.json's view list loaded with its images (LoadScanFromDescriptor,
// docs/FORMATS.md): the input is the scan.json; beside it are a 64x48 colour image c.png, a depth
// image d.png (1.5 m at depth scale 1000) and an intrinsics file k.txt, so views that name them
// reach the image, depth-range and intrinsics checks, the view limit and the ground-truth logic.
#include <opencv2/core.hpp>

#include "fuzz_input.hpp"
#include "io/image_codec.hpp"
#include "zeroreg/io.hpp"

namespace {

void WriteFiles() {
  const auto& folder = zeroreg::fuzz::Folder();
  const auto write = [&](const char* name, const std::vector<std::uint8_t>& bytes) {
    std::ofstream((folder / name).string(), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  };
  write("c.png", zeroreg::detail::EncodePng(cv::Mat(48, 64, CV_8UC3, cv::Scalar(30, 120, 200))));
  cv::Mat depth(48, 64, CV_16UC1, cv::Scalar(1500));
  depth(cv::Rect(0, 0, 16, 12)).setTo(0);
  write("d.png", zeroreg::detail::EncodePng(depth));
  std::ofstream((folder / "k.txt").string()) << "60 0 32\n0 60 24\n0 0 1\n";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool written = (WriteFiles(), true);
  (void)written;
  const std::string path = zeroreg::fuzz::WriteInput(data, size, "scan.json");
  return zeroreg::fuzz::Run([&] { zeroreg::LoadScanFromDescriptor(path); });
}
