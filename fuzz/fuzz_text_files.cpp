// libFuzzer harness for the whitespace-separated text files: gt.log / est.log, gt.info, poses and
// intrinsics. The first input byte picks the reader, the rest is the file.
#include "fuzz_input.hpp"
#include "zeroreg/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string path = zeroreg::fuzz::WriteInput(data + 1, size - 1, "input.txt");
  return zeroreg::fuzz::Run([&] {
    switch (data[0] % 4) {
      case 0:
        zeroreg::ReadLogFile(path);
        break;
      case 1:
        zeroreg::ReadInfoFile(path);
        break;
      case 2:
        zeroreg::ReadPoseFile(path);
        break;
      default:
        zeroreg::ReadIntrinsicsFile(path, 640, 480);
    }
  });
}
