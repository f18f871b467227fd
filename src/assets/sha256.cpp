// SHA-256 following FIPS 180-4 (§4.1.2 functions, §4.2.2 constants, §5.1.1 padding,
// §5.3.3 initial hash value, §6.2.2 hash computation).
#include "assets/sha256.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>

#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#include <immintrin.h>
#define ZEROREG_SHA256_X86 1
#endif

namespace zeroreg::detail {
namespace {

// K_0..K_63: first 32 bits of the fractional parts of the cube roots of the first 64 primes
// (FIPS 180-4 §4.2.2). Regenerated here with exact integer cube roots and checked by the
// known-answer tests.
constexpr std::array<std::uint32_t, 64> kRoundConstants = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2,
};

// H^(0): first 32 bits of the fractional parts of the square roots of the first 8 primes (§5.3.3).
constexpr std::array<std::uint32_t, 8> kInitialHash = {
    0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19,
};

constexpr std::size_t kBlockBytes = 64;

inline std::uint32_t RotateRight(std::uint32_t x, unsigned n) {
  return (x >> n) | (x << (32U - n));
}

// Message words are big-endian (§3.1).
inline std::uint32_t LoadBigEndian32(const std::uint8_t* p) {
  return (static_cast<std::uint32_t>(p[0]) << 24) | (static_cast<std::uint32_t>(p[1]) << 16) |
         (static_cast<std::uint32_t>(p[2]) << 8) | static_cast<std::uint32_t>(p[3]);
}

#if ZEROREG_SHA256_X86
bool CpuHasShaExtensions() {
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!__get_cpuid(1, &eax, &ebx, &ecx, &edx)) return false;
  const bool ssse3 = (ecx & (1U << 9)) != 0, sse41 = (ecx & (1U << 19)) != 0;
  if (!__get_cpuid_count(7, 0, &eax, &ebx, &ecx, &edx)) return false;
  return ssse3 && sse41 && (ebx & (1U << 29)) != 0;  // CPUID.(EAX=7,ECX=0):EBX.SHA[bit 29]
}

// The same compression function on the SHA extensions. The instructions keep the working
// variables as two vectors, (a, b, e, f) and (c, d, g, h) (sha256rnds2 does two rounds of
// §6.2.2 step 3 on them); the message schedule of step 1 is four words at a time:
// W[t..t+3] = sigma1 terms (sha256msg2) of W[t-16..] + sigma0(W[t-15..]) (sha256msg1) + W[t-7..].
__attribute__((target("sha,sse4.1,ssse3"))) void ProcessBlockShaExtensions(
    std::uint32_t* state, const std::uint8_t* block) {
  const __m128i byte_swap = _mm_set_epi64x(0x0c0d0e0f08090a0bULL, 0x0405060700010203ULL);
  // state = a b c d | e f g h (lowest word first) -> abef = (f e b a), cdgh = (h g d c).
  __m128i abcd = _mm_loadu_si128(reinterpret_cast<const __m128i*>(state));
  __m128i efgh = _mm_loadu_si128(reinterpret_cast<const __m128i*>(state + 4));
  abcd = _mm_shuffle_epi32(abcd, 0xB1);  // b a d c
  efgh = _mm_shuffle_epi32(efgh, 0x1B);  // h g f e
  __m128i abef = _mm_alignr_epi8(abcd, efgh, 8);
  __m128i cdgh = _mm_blend_epi16(efgh, abcd, 0xF0);
  const __m128i abef_start = abef, cdgh_start = cdgh;

  __m128i w[4];  // W[4i..4i+3] of the last four groups, indexed by i mod 4
  for (int i = 0; i < 16; ++i) {
    __m128i& group = w[i & 3];
    if (i < 4) {
      group = _mm_shuffle_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(block + 16 * i)),
                               byte_swap);
    } else {
      const __m128i& last = w[(i + 3) & 3];                                // W[4i-4..4i-1]
      const __m128i w_minus_7 = _mm_alignr_epi8(last, w[(i + 2) & 3], 4);  // W[4i-7..4i-4]
      group = _mm_sha256msg2_epu32(
          _mm_add_epi32(_mm_sha256msg1_epu32(group, w[(i + 1) & 3]), w_minus_7), last);
    }
    __m128i message = _mm_add_epi32(
        group, _mm_loadu_si128(reinterpret_cast<const __m128i*>(&kRoundConstants[4 * i])));
    cdgh = _mm_sha256rnds2_epu32(cdgh, abef, message);
    message = _mm_shuffle_epi32(message, 0x0E);  // the upper two words for the next two rounds
    abef = _mm_sha256rnds2_epu32(abef, cdgh, message);
  }
  abef = _mm_add_epi32(abef, abef_start);
  cdgh = _mm_add_epi32(cdgh, cdgh_start);
  // Back to a b c d | e f g h.
  const __m128i feba = _mm_shuffle_epi32(abef, 0x1B);
  const __m128i dchg = _mm_shuffle_epi32(cdgh, 0xB1);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(state), _mm_blend_epi16(feba, dchg, 0xF0));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(state + 4), _mm_alignr_epi8(dchg, feba, 8));
}
#endif

std::atomic<bool> g_allow_sha_extensions{true};

bool UseShaExtensions() {
#if ZEROREG_SHA256_X86
  static const bool available = CpuHasShaExtensions();
  return available && g_allow_sha_extensions.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

}  // namespace

bool Sha256UseShaExtensions(bool allow) {
  g_allow_sha_extensions = allow;
  return UseShaExtensions();
}

void Sha256::ProcessBlock(const std::uint8_t* block) {
#if ZEROREG_SHA256_X86
  if (UseShaExtensions()) {
    ProcessBlockShaExtensions(state_.data(), block);
    return;
  }
#endif
  ProcessBlockPortable(block);
}

Sha256::Sha256() : state_(kInitialHash) {}

void Sha256::ProcessBlockPortable(const std::uint8_t* block) {
  // Message schedule W_0..W_63 (§6.2.2 step 1), with the small sigma functions of §4.1.2.
  std::array<std::uint32_t, 64> w{};
  for (std::size_t t = 0; t < 16; ++t) w[t] = LoadBigEndian32(block + 4 * t);
  for (std::size_t t = 16; t < 64; ++t) {
    const std::uint32_t sigma0 =
        RotateRight(w[t - 15], 7) ^ RotateRight(w[t - 15], 18) ^ (w[t - 15] >> 3);
    const std::uint32_t sigma1 =
        RotateRight(w[t - 2], 17) ^ RotateRight(w[t - 2], 19) ^ (w[t - 2] >> 10);
    w[t] = w[t - 16] + sigma0 + w[t - 7] + sigma1;
  }

  // Working variables a..h (steps 2-3); all additions are mod 2^32 by unsigned wrap-around.
  std::uint32_t a = state_[0], b = state_[1], c = state_[2], d = state_[3];
  std::uint32_t e = state_[4], f = state_[5], g = state_[6], h = state_[7];
  for (std::size_t t = 0; t < 64; ++t) {
    const std::uint32_t big_sigma1 = RotateRight(e, 6) ^ RotateRight(e, 11) ^ RotateRight(e, 25);
    const std::uint32_t choose = (e & f) ^ (~e & g);
    const std::uint32_t t1 = h + big_sigma1 + choose + kRoundConstants[t] + w[t];
    const std::uint32_t big_sigma0 = RotateRight(a, 2) ^ RotateRight(a, 13) ^ RotateRight(a, 22);
    const std::uint32_t majority = (a & b) ^ (a & c) ^ (b & c);
    const std::uint32_t t2 = big_sigma0 + majority;
    h = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }

  // Step 4: next intermediate hash value.
  state_[0] += a;
  state_[1] += b;
  state_[2] += c;
  state_[3] += d;
  state_[4] += e;
  state_[5] += f;
  state_[6] += g;
  state_[7] += h;
}

void Sha256::Update(const void* data, std::size_t size) {
  if (finished_) throw std::logic_error("Sha256::Update called after HexDigest");
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  message_bytes_ += size;

  // Top up a partially filled block first.
  if (pending_size_ > 0) {
    const std::size_t take = std::min(size, kBlockBytes - pending_size_);
    std::memcpy(pending_.data() + pending_size_, bytes, take);
    pending_size_ += take;
    bytes += take;
    size -= take;
    if (pending_size_ < kBlockBytes) return;
    ProcessBlock(pending_.data());
    pending_size_ = 0;
  }
  // Whole blocks straight from the caller's buffer (no copy).
  while (size >= kBlockBytes) {
    ProcessBlock(bytes);
    bytes += kBlockBytes;
    size -= kBlockBytes;
  }
  if (size > 0) {
    std::memcpy(pending_.data(), bytes, size);
    pending_size_ = size;
  }
}

std::string Sha256::HexDigest() {
  if (finished_) throw std::logic_error("Sha256::HexDigest called twice");
  // Padding (§5.1.1): a 1 bit, zeros up to 448 mod 512 bits, then the length l in bits as a
  // 64-bit big-endian integer. Messages are whole bytes here, so the 1 bit is the byte 0x80.
  const std::uint64_t length_bits = message_bytes_ * 8U;
  const std::size_t zeros =
      (pending_size_ < 56 ? 56 - pending_size_ : 56 + kBlockBytes - pending_size_) - 1;
  std::array<std::uint8_t, 1 + 63 + 8> padding{};
  padding[0] = 0x80;
  for (int i = 0; i < 8; ++i) {
    padding[1 + zeros + i] = static_cast<std::uint8_t>(length_bits >> (56 - 8 * i));
  }
  Update(padding.data(), 1 + zeros + 8);
  finished_ = true;

  static const char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(64);
  for (std::uint32_t word : state_) {
    for (int shift = 28; shift >= 0; shift -= 4) hex.push_back(kHex[(word >> shift) & 0xFU]);
  }
  return hex;
}

std::string Sha256Hex(const std::string& bytes) {
  Sha256 hasher;
  hasher.Update(bytes);
  return hasher.HexDigest();
}

}  // namespace zeroreg::detail
