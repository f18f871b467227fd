// libFuzzer harness for scan.json (ReadScanDescriptor, docs/FORMATS.md).
#include "fuzz_input.hpp"
#include "zeroreg/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zeroreg::fuzz::WriteInput(data, size, "scan.json");
  return zeroreg::fuzz::Run([&] { zeroreg::ReadScanDescriptor(path); });
}
