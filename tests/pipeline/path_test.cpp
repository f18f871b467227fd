// RegistrationResult::path is data; its name is what the JSON result, the records and Python carry.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "pipeline/sources/pose_source.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {
namespace {

TEST(Path, NamesAreTheStringsTheJsonResultHasAlwaysCarried) {
  EXPECT_EQ(PathName(Path{}), "");
  EXPECT_EQ(PathName({PathSource::kObject}), "object");
  EXPECT_EQ(PathName({PathSource::kImage}), "image");
  EXPECT_EQ(PathName({PathSource::kImageFallback}), "image-fallback");
  EXPECT_EQ(PathName({PathSource::kImageRival}), "image-rival");
  EXPECT_EQ(PathName({PathSource::kObjectCentroids}), "object-centroids");
  EXPECT_EQ(PathName({PathSource::kObject, PathEstimator::kClique}), "object clique");
  EXPECT_EQ(PathName({PathSource::kImage, PathEstimator::kRansac}), "image ransac");
  EXPECT_EQ(PathName({PathSource::kGeometry, PathEstimator::kClique}), "geometry clique");
  EXPECT_EQ(PathName({PathSource::kObjectPairs, PathEstimator::kClique}), "object-pairs clique");
  EXPECT_EQ(PathName({PathSource::kImageTurned90, PathEstimator::kRansac}),
            "image-turned-90 ransac");
  EXPECT_EQ(PathName({PathSource::kImageTurned180, PathEstimator::kRansac}),
            "image-turned-180 ransac");
  EXPECT_EQ(PathName({PathSource::kImageTurned270, PathEstimator::kClique}),
            "image-turned-270 clique");
  EXPECT_EQ(PathName({PathSource::kPrior}), "prior");
  EXPECT_EQ(PathName({PathSource::kPrior, PathEstimator::kMethod, true}), "prior icp");
}

TEST(Path, EveryPathHasItsOwnName) {
  std::set<std::string> names;
  int paths = 0;
  for (int s = static_cast<int>(PathSource::kObject); s <= static_cast<int>(PathSource::kPrior);
       ++s) {
    for (const PathEstimator e :
         {PathEstimator::kMethod, PathEstimator::kRansac, PathEstimator::kClique}) {
      for (const bool icp : {false, true}) {
        names.insert(PathName({static_cast<PathSource>(s), e, icp}));
        ++paths;
      }
    }
  }
  EXPECT_EQ(static_cast<int>(names.size()), paths);
  EXPECT_EQ(names.count(""), 0u);
}

TEST(Path, EqualityComparesEveryField) {
  const Path geometry{PathSource::kGeometry, PathEstimator::kClique};
  EXPECT_EQ(geometry, (Path{PathSource::kGeometry, PathEstimator::kClique}));
  EXPECT_NE(geometry, (Path{PathSource::kGeometry, PathEstimator::kRansac}));
  EXPECT_NE(geometry, (Path{PathSource::kImage, PathEstimator::kClique}));
  EXPECT_NE((Path{PathSource::kPrior}), (Path{PathSource::kPrior, PathEstimator::kMethod, true}));
}

TEST(Path, EstimatorNamesMapToTheirPathEstimator) {
  EXPECT_EQ(PathEstimatorOf("ransac"), PathEstimator::kRansac);
  EXPECT_EQ(PathEstimatorOf("clique"), PathEstimator::kClique);
}

TEST(Path, TheJsonResultWritesTheName) {
  RegistrationResult r;
  r.path = {PathSource::kImageTurned180, PathEstimator::kRansac};
  EXPECT_EQ(ResultToJson(r, false).at("path").get<std::string>(), "image-turned-180 ransac");
  r.path = {};
  EXPECT_EQ(ResultToJson(r, false).at("path").get<std::string>(), "");
}

}  // namespace
}  // namespace zeroreg
