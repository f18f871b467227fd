// SHA-256 (FIPS 180-4) written for zeroreg so that asset checks need no crypto library.
//
// Internal header: the public entry point is zeroreg::Sha256OfFile (include/zeroreg/assets.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace zeroreg::detail {

// Streaming SHA-256: feed bytes with Update() in pieces of any size (the digest does not depend
// on how the input is split), then call HexDigest() once.
class Sha256 {
 public:
  Sha256();

  void Update(const void* data, std::size_t size);
  void Update(const std::string& bytes) { Update(bytes.data(), bytes.size()); }

  // Pads the message (FIPS 180-4 §5.1.1), processes the last block(s) and returns the digest as 64
  // lowercase hex digits. Further Update()/HexDigest() calls throw std::logic_error.
  std::string HexDigest();

 private:
  // One 512-bit block through the compression function (FIPS 180-4 §6.2.2).
  void ProcessBlock(const std::uint8_t* block);
  void ProcessBlockPortable(const std::uint8_t* block);

  std::array<std::uint32_t, 8> state_;      // H^(i), the intermediate hash value
  std::array<std::uint8_t, 64> pending_{};  // bytes not yet forming a full block
  std::size_t pending_size_ = 0;
  std::uint64_t message_bytes_ = 0;  // total length so far; the padding stores it in bits
  bool finished_ = false;
};

// Whether Sha256 uses the x86 SHA extensions (SHA-NI: sha256rnds2 / sha256msg1 / sha256msg2, on
// Intel since Goldmont / Ice Lake and AMD since Zen), detected once with cpuid. They compute the
// same compression function with far less CPU (perf of a registration: sha256's share fell from
// 4.4 % to 0.6 %), which matters because every process verifies its model files (~8 MB) before
// loading them. `allow` = false forces the portable code (for the tests that compare the two
// paths); returns the path now in use.
bool Sha256UseShaExtensions(bool allow = true);

// SHA-256 of an in-memory byte string, as 64 lowercase hex digits.
std::string Sha256Hex(const std::string& bytes);

}  // namespace zeroreg::detail
