// libFuzzer harness for the config: a JSON file (ReadConfigFile) or, when the input holds an '=',
// a --set assignment (ApplyConfigOverride). Whatever is accepted must pass ValidateConfig.
#include <cstring>

#include "fuzz_input.hpp"
#include "zeroreg/json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return zeroreg::fuzz::Run([&] {
    zeroreg::PipelineConfig config;
    if (std::memchr(data, '=', size) != nullptr) {
      zeroreg::ApplyConfigOverride(std::string(reinterpret_cast<const char*>(data), size), &config);
    } else {
      config = zeroreg::ReadConfigFile(zeroreg::fuzz::WriteInput(data, size, "config.json"));
    }
    zeroreg::ValidateConfig(config, "fuzzed config");
  });
}
