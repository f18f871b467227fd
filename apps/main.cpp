// zeroreg: zero-shot registration of RGB-D scans (ZeroReg, CVPR 2025).
#include <iostream>
#include <map>

#include "commands.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/version.hpp"

int main(int argc, char** argv) {
  using namespace zeroreg::cli;
  CLI::App app{"zeroreg: register two RGB-D scans with 2D foundation models, no 3D training"};
  app.set_version_flag("--version", "zeroreg " ZEROREG_VERSION);
  app.require_subcommand(1);
  std::map<CLI::App*, Runner> runners;
  auto add = [&](const char* name, Runner (*adder)(CLI::App&), const char* help) {
    CLI::App* sub = app.add_subcommand(name, help);
    runners[sub] = adder(*sub);
  };
  add("register", AddRegisterCommand, "estimate T_target_source between two scans");
  add("fuse", AddFuseCommand, "TSDF-fuse frames into a 3DMatch-style fragment (cached)");
  add("info", AddInfoCommand, "show the effective config, assets and a scan's contents");
  add("eval", AddEvalCommand, "evaluate on 3DMatch/3DLoMatch or frame pairs, with baselines");
  add("report", AddReportCommand, "make a self-contained HTML page of a register or eval folder");
  add("bench-models", AddBenchModelsCommand,
      "time every ONNX model per image on each inference engine");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    for (const auto& [sub, run] : runners) {
      if (sub->parsed()) return run();
    }
  } catch (const zeroreg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return kExitInternalError;
  }
  return kExitInternalError;
}
