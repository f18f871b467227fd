// ImagePlanes gives cv::dnn::blobFromImage's values bit for bit (so replacing it changes no model
// output), for XFeat's setting (1/255, RGB) and YOLOX's (1, BGR), on real frames of two scenes and
// on an image whose rows are not contiguous (a region of a larger one).
#include "inference/image_tensor.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>

#include "detect/perception_test_util.hpp"
#include "test_paths.hpp"

namespace zeroreg {
namespace {

TEST(ImageTensor, PlanesAreBlobFromImage) {
  for (const std::string& path :
       {perception_test::FramePath(0, "color.jpg"),
        testing::SharedDir() + "/data/hololens-office/frames/frame-000003.color.jpg"}) {
    const cv::Mat full = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(full.empty()) << path;
    const cv::Mat region = full(cv::Rect(3, 5, full.cols - 10, full.rows - 20));
    for (const cv::Mat& img : {full, region}) {
      for (const auto& [scale, swap] : {std::pair{1.0 / 255.0, true}, std::pair{1.0, false}}) {
        const cv::Mat blob = cv::dnn::blobFromImage(img, scale, img.size(), cv::Scalar(), swap,
                                                    /*crop=*/false);
        const std::vector<float> planes = ImagePlanes(img, scale, swap);
        ASSERT_EQ(planes.size(), blob.total()) << path;
        EXPECT_EQ(std::memcmp(planes.data(), blob.ptr<float>(), planes.size() * sizeof(float)), 0)
            << path << " scale " << scale << " swap " << swap;
      }
    }
  }
}

}  // namespace
}  // namespace zeroreg
