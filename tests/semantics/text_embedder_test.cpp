#include "semantics/text_embedder.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "test_paths.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

std::string Assets() { return testing::RepoDir() + "/assets"; }

TEST(ClipTable, ReadsTheCocoTableWithItsShape) {
  const Eigen::MatrixXf coco =
      ReadNpyMatrix(Assets() + "/clip_text_embeddings_detic/coco_clip_a+cname.npy");
  EXPECT_EQ(coco.rows(), 80);
  EXPECT_EQ(coco.cols(), 512);
  // Detic stored rows un-normalised, norms 8-13.4 (MANIFEST).
  EXPECT_GT(coco.row(0).norm(), 7.9f);
  EXPECT_LT(coco.row(0).norm(), 13.5f);
}

TEST(ClipTable, CouchIsCloseToLvisSofaAsMeasuredInTheManifest) {
  const auto all = DefaultClipTables(Assets());
  ClipTableEmbedder coco_and_lvis({all[0], all[3]});  // COCO, LVIS
  const auto couch = coco_and_lvis.Embed("couch"), sofa = coco_and_lvis.Embed("sofa");
  ASSERT_TRUE(couch && sofa);
  EXPECT_NEAR(couch->dot(*sofa), 0.946f, 0.002f);  // MANIFEST: couch -> sofa 0.946
  EXPECT_NEAR(couch->norm(), 1.0f, 1e-5f);
}

TEST(ClipTable, LookupIsCaseInsensitiveAndMapsLvisUnderscores) {
  ClipTableEmbedder embedder(DefaultClipTables(Assets()));
  EXPECT_EQ(embedder.dimension(), 512);
  const auto chair = embedder.Embed("chair"), chair_upper = embedder.Embed("Chair");
  ASSERT_TRUE(chair && chair_upper);
  EXPECT_NEAR(chair->dot(*chair_upper), 1.0f, 1e-5f);
  // "aerosol can" exists only in LVIS, spelled aerosol_can.
  EXPECT_TRUE(embedder.Embed("aerosol can").has_value());
  EXPECT_TRUE(embedder.Embed("aerosol_can").has_value());
  EXPECT_FALSE(embedder.Embed("flux capacitor").has_value());
}

TEST(ClipTable, TruncatedOrForeignFilesRaiseInputErrorNamingTheFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("zeroreg_npy_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string source = Assets() + "/clip_text_embeddings_detic/coco_clip_a+cname.npy";
  const std::string truncated = (dir / "truncated.npy").string();
  fs::copy_file(source, truncated, fs::copy_options::overwrite_existing);
  fs::resize_file(truncated, 5000);
  const std::string text = (dir / "text.npy").string();
  std::ofstream(text) << "not numpy";
  for (const auto& [path, problem] : {std::pair{truncated, "truncated"}, {text, "bad magic"}}) {
    try {
      ReadNpyMatrix(path);
      ADD_FAILURE() << "expected InputError for " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace zeroreg
