// SHA-256 known-answer tests (FIPS 180-4 examples / NIST CAVS short messages) for our own
// implementation, through the streaming class and through Sha256OfFile.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "assets/sha256.hpp"
#include "assets_test_util.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using testing::TempDir;
using testing::WriteFile;

const std::string kNist448 = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";

// (message, digest) pairs; digests from FIPS 180-4 / NIST examples and, for the padding-boundary
// lengths, from Python's hashlib.
std::vector<std::pair<std::string, std::string>> KnownAnswers() {
  return {
      {"", "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"},
      {"abc", "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"},
      {kNist448, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"},
      {std::string(1000000, 'a'),
       "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0"},
      // Lengths around the 55/56-byte padding boundary and block multiples (§5.1.1).
      {std::string(55, 'a'), "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318"},
      {std::string(56, 'a'), "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a"},
      {std::string(63, 'a'), "7d3e74a05d7db15bce4ad9ec0658ea98e3f06eeecf16b4c6fff2da457ddc2f34"},
      {std::string(64, 'a'), "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb"},
      {std::string(65, 'a'), "635361c48bb9eab14198e76ea8ab7f1a41685d6ad62aa9146d301d4f17eb0ae0"},
      {std::string(119, 'a'), "31eba51c313a5c08226adf18d4a359cfdfd8d2e816b13f4af952f7ea6584dcfb"},
      {std::string(120, 'a'), "2f3d335432c70b580af0e8e1b3674a7c020d683aa5f73aaaedfdc55af904c21c"},
      {std::string(127, 'a'), "c57e9278af78fa3cab38667bef4ce29d783787a2f731d4e12200270f0c32320a"},
      {std::string(128, 'a'), "6836cf13bac400e9105071cd6af47084dfacad4e5e302c94bfed24e013afb73e"},
  };
}

TEST(AssetsSha256, KnownAnswersInOneCall) {
  for (const auto& [message, digest] : KnownAnswers()) {
    EXPECT_EQ(detail::Sha256Hex(message), digest) << "message length " << message.size();
  }
}

// Both compression functions (the SHA extensions where the CPU has them, and the portable code)
// give every known answer; on a CPU without the extensions both runs take the portable code.
TEST(AssetsSha256, KnownAnswersOnBothCodePaths) {
  for (bool allow : {false, true}) {
    const bool extensions = detail::Sha256UseShaExtensions(allow);
    EXPECT_TRUE(allow || !extensions);
    for (const auto& [message, digest] : KnownAnswers()) {
      EXPECT_EQ(detail::Sha256Hex(message), digest)
          << "message length " << message.size() << (extensions ? ", SHA extensions" : "");
    }
  }
  detail::Sha256UseShaExtensions(true);
}

TEST(AssetsSha256, DigestDoesNotDependOnHowInputIsSplit) {
  // 0..255 repeated: every byte value, 1280 bytes = 20 blocks. Digest from hashlib.
  std::string message;
  for (int r = 0; r < 5; ++r) {
    for (int b = 0; b < 256; ++b) message.push_back(static_cast<char>(b));
  }
  const std::string expected = "d414b085826eb06778483ba35564dc849e643359f69ed9747878ba6e54985bed";
  for (std::size_t piece : {1, 3, 55, 63, 64, 65, 100, 1279}) {
    detail::Sha256 hasher;
    for (std::size_t i = 0; i < message.size(); i += piece) {
      hasher.Update(message.data() + i, std::min(piece, message.size() - i));
    }
    EXPECT_EQ(hasher.HexDigest(), expected) << "pieces of " << piece << " bytes";
  }
}

TEST(AssetsSha256, MisuseAfterDigestThrows) {
  detail::Sha256 hasher;
  hasher.Update("abc");
  hasher.HexDigest();
  EXPECT_THROW(hasher.Update("x"), std::logic_error);
  EXPECT_THROW(hasher.HexDigest(), std::logic_error);
}

TEST(AssetsSha256, FileKnownAnswers) {
  // Through files, so the chunked reader is covered too (1,000,000 bytes = 15 full 64 KiB chunks
  // plus a partial one).
  TempDir dir;
  int index = 0;
  for (const auto& [message, digest] : KnownAnswers()) {
    const std::string path = dir / ("kat" + std::to_string(index++));
    WriteFile(path, message);
    EXPECT_EQ(Sha256OfFile(path), digest) << "message length " << message.size();
  }
}

TEST(AssetsSha256, RealModelFileMatchesManifest) {
  const std::string path = testing::SharedModelsDir() + "/xfeat/xfeat_640x640.onnx";
  if (!std::ifstream(path)) GTEST_SKIP() << path << " not available";
  // sha256 given in ../shared/models/xfeat/MANIFEST.md.
  EXPECT_EQ(Sha256OfFile(path), "54041f61f0d9b1968451a65fe0fd79e96692b1d8266c54a6939a73e847df5988");
}

TEST(AssetsSha256, UnreadableFilesThrowInputErrorNamingThePath) {
  TempDir dir;
  const std::string missing = dir / "no_such_file.onnx";
  try {
    Sha256OfFile(missing);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing + ": cannot be read"), std::string::npos)
        << e.what();
  }
  try {
    Sha256OfFile(dir.path());
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.path() + ": is a directory"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace zeroreg
