// Redkitchen frames with their YOLOX detections, shared by the segmentation tests.
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "detect/detector.hpp"
#include "detect/perception_test_util.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg::mask_test {

struct Frame {
  std::string name;
  cv::Mat bgr, depth;
  std::vector<Detection> detections;
};

// Frame `id` and its YOLOX detections, loaded once per test program (the detector is ~50 ms).
inline const Frame& RedkitchenFrame(int id) {
  static std::map<int, Frame> cache;
  auto it = cache.find(id);
  if (it == cache.end()) {
    Frame f;
    f.name = perception_test::FramePath(id, "color.jpg");
    f.bgr = ReadColorImage(f.name);
    f.depth = ReadDepthImage(perception_test::FramePath(id, "depth.png"), 1000.0);
    f.detections =
        MakeDetector(DetectorConfig{}, perception_test::ModelPaths())->Detect(f.bgr, f.name);
    it = cache.emplace(id, std::move(f)).first;
  }
  return it->second;
}

}  // namespace zeroreg::mask_test
