// Registers two scans given on the command line with the default pipeline and prints the
// transform; with a third argument, writes the result as the CLI does (under "result").
//
//   register_pair SOURCE TARGET [RESULT.json]      (scans as the CLI takes them, e.g. DIR@N)
#include <zeroreg/error.hpp>
#include <zeroreg/io.hpp>
#include <zeroreg/json.hpp>
#include <zeroreg/register.hpp>
#include <zeroreg/version.hpp>

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: " << argv[0] << " SOURCE TARGET [RESULT.json]\n";
    return 2;
  }
  try {
    const zeroreg::Scan source = zeroreg::LoadScan(argv[1]);
    const zeroreg::Scan target = zeroreg::LoadScan(argv[2]);
    const zeroreg::RegistrationResult r = zeroreg::Register(source, target);
    std::cout << "zeroreg " << ZEROREG_VERSION << ": " << (r.valid ? "valid" : "not valid") << " ("
              << r.reason << ")\nT_target_source =\n"
              << r.T_target_source << "\n";
    if (argc == 4) {
      std::ofstream(argv[3]) << nlohmann::json{{"result", zeroreg::ResultToJson(r, false)}}.dump(2)
                             << "\n";
    }
    return r.valid ? 0 : 1;
  } catch (const zeroreg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
}
