// libFuzzer harness for precomputed detections (docs/PERCEPTION.md): the input is
// <dir>/frame.json, read for a 64x48 image named frame.png.
#include <opencv2/core.hpp>

#include "detect/backends.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  zeroreg::fuzz::WriteInput(data, size, "frame.json");
  static const cv::Mat image(48, 64, CV_8UC3, cv::Scalar(0, 0, 0));
  return zeroreg::fuzz::Run([&] {
    zeroreg::DetectorConfig config;
    config.backend = "file";
    config.detections_dir = zeroreg::fuzz::Folder().string();
    zeroreg::FileDetector(config).Detect(image, "frame.png");
  });
}
