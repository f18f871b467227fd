// Shared by the libFuzzer harnesses (fuzz/README.md): the parsers read files, so each input is
// written to a per-process temporary file first. A parser may reject an input only with
// InputError; anything else (another exception, a crash, a sanitizer report) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "zeroreg/error.hpp"

namespace zeroreg::fuzz {

// A folder of its own per process (libFuzzer -jobs runs several), created once.
inline const std::filesystem::path& Folder() {
  static const std::filesystem::path folder = [] {
    const auto p =
        std::filesystem::temp_directory_path() / ("zeroreg_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    return p;
  }();
  return folder;
}

// Writes the input to Folder()/name and returns the path.
inline std::string WriteInput(const uint8_t* data, size_t size, const std::string& name) {
  const std::string path = (Folder() / name).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs `parse`, accepting InputError as the only way to refuse an input.
template <typename Parse>
int Run(Parse parse) {
  try {
    parse();
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace zeroreg::fuzz
