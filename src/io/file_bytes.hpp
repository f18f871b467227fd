// Reading a whole binary file in one call. std::istreambuf_iterator reads a byte at a time: for a
// 6 MB model graph that was ~15 ms of a registration's start-up, for a colour and a depth image
// a few ms each.
#pragma once

#include <cstdint>
#include <fstream>
#include <optional>
#include <vector>

namespace zeroreg {

// The bytes of the open file `in` from its start, or nullopt when it cannot be sized or read.
// Byte is char or std::uint8_t.
template <typename Byte>
std::optional<std::vector<Byte>> ReadAllBytes(std::ifstream& in) {
  static_assert(sizeof(Byte) == 1, "a byte type");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (!in || size < 0) return std::nullopt;
  in.seekg(0, std::ios::beg);
  std::vector<Byte> bytes(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) return std::nullopt;
  return bytes;
}

}  // namespace zeroreg
