// libFuzzer harness for the pair lists: a list folder (pairs.txt + gt.log, ReadPairList) or a
// --pairs file (ReadPairsFile). The first byte picks the reader; for a list folder, the input is
// split at the first NUL byte into pairs.txt and gt.log.
#include <algorithm>
#include <vector>

#include "eval/pair_list.hpp"
#include "eval/protocols.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t* begin = data + 1;
  const uint8_t* end = data + size;
  return zeroreg::fuzz::Run([&] {
    if (data[0] % 2 == 0) {
      zeroreg::ReadPairsFile(zeroreg::fuzz::WriteInput(begin, end - begin, "pairs-file.txt"));
      return;
    }
    const uint8_t* split = std::find(begin, end, 0);
    zeroreg::fuzz::WriteInput(begin, split - begin, "pairs.txt");
    const uint8_t* log = split == end ? end : split + 1;
    zeroreg::fuzz::WriteInput(log, end - log, "gt.log");
    static const std::vector<int> frames = {0, 1, 2, 3, 4, 5, 10, 20, 50, 100};
    zeroreg::ReadPairList(zeroreg::fuzz::Folder().string(), frames, "data", "scene");
  });
}
