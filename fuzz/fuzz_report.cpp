// libFuzzer harness for `zeroreg report` on an eval folder (BuildReportHtml, src/viz/report.hpp):
// the input holds pairs.jsonl, summary.md and summary.json, separated by lines holding a single
// NUL byte ("\n\0\n"); a missing part leaves that file out of the folder.
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "viz/report.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator("\n\0\n", 3);
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t end = input.find(separator, start);
    parts.push_back(input.substr(start, end == std::string::npos ? end : end - start));
    if (end == std::string::npos || parts.size() == 3) break;
    start = end + separator.size();
  }
  const auto folder = zeroreg::fuzz::Folder() / "results";
  std::error_code ec;
  std::filesystem::remove_all(folder, ec);
  std::filesystem::create_directories(folder);
  const char* names[] = {"pairs.jsonl", "summary.md", "summary.json"};
  for (size_t k = 0; k < parts.size(); ++k) {
    std::ofstream((folder / names[k]).string(), std::ios::binary) << parts[k];
  }
  return zeroreg::fuzz::Run([&] { zeroreg::BuildReportHtml(folder.string()); });
}
