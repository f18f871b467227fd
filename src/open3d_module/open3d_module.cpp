#include "open3d_module/open3d_module.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "assets/assets_internal.hpp"
#include "zeroreg/error.hpp"

#if !defined(ZEROREG_INSTALL_OPEN3D_MODULE) || !defined(ZEROREG_INSTALL_LIBDIR) || \
    !defined(ZEROREG_BUILD_OPEN3D_MODULE)
#error \
    "ZEROREG_INSTALL_OPEN3D_MODULE, ZEROREG_INSTALL_LIBDIR and ZEROREG_BUILD_OPEN3D_MODULE come from the build (CMakeLists.txt)"
#endif

namespace zeroreg::open3d_module {
namespace {

namespace fs = std::filesystem;

// What Load() found: the module's table and the file it came from.
struct Loaded {
  const Api* api = nullptr;
  std::string path;
};

Loaded Load() {
  std::string tried;
  for (const std::string& path : ModuleSearchPaths()) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      tried += "\n  " + path + ": no such file";
      continue;
    }
    // RTLD_LOCAL: Open3D's symbols stay out of the global namespace (the Python extension is
    // loaded RTLD_LOCAL too). Never closed: the table points into it for the process's life.
    // An absolute path: dlopen would look a bare file name up in the library path instead.
    const std::string file = fs::absolute(path, ec).string();
    void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* error = ::dlerror();
      std::string why = error != nullptr ? error : "cannot be loaded";
      if (why.rfind(file + ": ", 0) == 0) why.erase(0, file.size() + 2);  // named once, below
      tried += "\n  " + path + ": " + why;
      continue;
    }
    using EntryPoint = const Api* (*)();
    const auto entry = reinterpret_cast<EntryPoint>(::dlsym(handle, kEntryPoint));
    if (entry == nullptr) {
      const char* why = ::dlerror();
      tried +=
          "\n  " + path + ": not a zeroreg Open3D module (" + (why != nullptr ? why : "") + ")";
      ::dlclose(handle);
      continue;
    }
    const Api* api = entry();
    if (api == nullptr || api->abi_version != kAbiVersion || api->layout != kLayout) {
      tried += "\n  " + path + ": a zeroreg Open3D module of another build (interface " +
               std::to_string(api != nullptr ? api->abi_version : -1) + "/" +
               std::to_string(api != nullptr ? api->layout : 0) + ", this build needs " +
               std::to_string(kAbiVersion) + "/" + std::to_string(kLayout) + ")";
      ::dlclose(handle);
      continue;
    }
    return {api, path};
  }
  throw MakeInputError(
      kFileName,
      "could not be loaded; it holds what zeroreg takes from Open3D (the geometry hypothesis's "
      "FPFH, point cloud files, TSDF fusion, the FPFH baseline) and is built and installed with "
      "zeroreg (docs/INSTALL.md); set $ZEROREG_OPEN3D_MODULE to its path. Looked in:" +
          tried);
}

}  // namespace

std::vector<std::string> ModuleSearchPaths() {
  // A path the user gave is the only one tried: a module found elsewhere instead would hide
  // that the given one is missing or broken.
  if (const char* env = std::getenv("ZEROREG_OPEN3D_MODULE"); env != nullptr && *env != '\0') {
    return {env};
  }
  std::vector<std::string> paths;
  const std::string self = detail::LoadedObjectPath();
  if (!self.empty()) {
    std::error_code ec;
    const fs::path resolved = fs::canonical(self, ec);
    const fs::path dir = (ec ? fs::path(self) : resolved).parent_path();
    paths.push_back((dir / kFileName).string());
    paths.push_back(
        (dir / ".." / ZEROREG_INSTALL_LIBDIR / "zeroreg" / kFileName).lexically_normal().string());
  }
  // The configured install prefix, then the build folder the library was compiled in (a program
  // of the user's linking the installed static library, run from anywhere).
  for (const std::string fixed : {ZEROREG_INSTALL_OPEN3D_MODULE, ZEROREG_BUILD_OPEN3D_MODULE}) {
    if (std::find(paths.begin(), paths.end(), fixed) == paths.end()) paths.push_back(fixed);
  }
  return paths;
}

namespace {

// A failed load is tried again on the next call (the error names what to fix), so the result is
// not a function-local static initialised once.
const Loaded& LoadedModule() {
  static std::mutex mutex;
  static Loaded loaded;
  std::lock_guard<std::mutex> lock(mutex);
  if (loaded.api == nullptr) loaded = Load();
  return loaded;
}

}  // namespace

const Api& Module() { return *LoadedModule().api; }

std::string LoadedModulePath() { return LoadedModule().path; }

}  // namespace zeroreg::open3d_module
