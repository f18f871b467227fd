// libFuzzer harness for pairs.jsonl, the eval records that `report`, `eval merge` and a resumed
// run read back (ReadPairsJsonl, src/eval/records.hpp).
#include "eval/records.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zeroreg::fuzz::WriteInput(data, size, "pairs.jsonl");
  return zeroreg::fuzz::Run([&] {
    bool dropped = false;
    zeroreg::ReadPairsJsonl(path, &dropped);
  });
}
