#include "open3d_module/open3d_module.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "zeroreg/error.hpp"

#if !defined(ZEROREG_INSTALL_OPEN3D_MODULE) || !defined(ZEROREG_INSTALL_LIBDIR) || \
    !defined(ZEROREG_BUILD_OPEN3D_MODULE)
#error \
    "ZEROREG_INSTALL_OPEN3D_MODULE, ZEROREG_INSTALL_LIBDIR and ZEROREG_BUILD_OPEN3D_MODULE come from the build (CMakeLists.txt)"
#endif

namespace zeroreg::open3d_module {
namespace {

namespace fs = std::filesystem;

// The program or shared object this code was linked into (the CLI, the test binary, the Python
// extension), as the dynamic loader knows it.
fs::path ThisObjectPath() {
  static const char anchor = 0;
  Dl_info info{};
  if (::dladdr(&anchor, &info) != 0 && info.dli_fname != nullptr &&
      std::strchr(info.dli_fname, '/') != nullptr) {
    std::error_code ec;
    const fs::path resolved = fs::canonical(info.dli_fname, ec);
    return ec ? fs::path(info.dli_fname) : resolved;
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe;
}

// The file Load() loaded the module from.
std::string& LoadedFrom() {
  static std::string path;
  return path;
}

const Api& Load() {
  std::string tried;
  for (const std::string& path : ModuleSearchPaths()) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      tried += "\n  " + path + ": no such file";
      continue;
    }
    // RTLD_LOCAL: Open3D's symbols stay out of the global namespace (the Python extension is
    // loaded RTLD_LOCAL too). Never closed: the table points into it for the process's life.
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = ::dlerror();
      tried += "\n  " + path + ": " + (why != nullptr ? why : "cannot be loaded");
      continue;
    }
    using EntryPoint = const Api* (*)();
    const auto entry = reinterpret_cast<EntryPoint>(::dlsym(handle, kEntryPoint));
    const Api* api = entry != nullptr ? entry() : nullptr;
    if (api == nullptr || api->abi_version != kAbiVersion) {
      tried += "\n  " + path + ": not a zeroreg Open3D module of this build (interface version " +
               std::to_string(api != nullptr ? api->abi_version : -1) + ", need " +
               std::to_string(kAbiVersion) + ")";
      continue;
    }
    LoadedFrom() = path;
    return *api;
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
  const fs::path self = ThisObjectPath();
  if (!self.empty()) {
    const fs::path dir = self.parent_path();
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

const Api& Module() {
  // A failed load is tried again on the next call (the error names what to fix), so the result is
  // not a function-local static.
  static std::mutex mutex;
  static const Api* loaded = nullptr;
  std::lock_guard<std::mutex> lock(mutex);
  if (loaded == nullptr) loaded = &Load();
  return *loaded;
}

std::string LoadedModulePath() {
  Module();
  return LoadedFrom();
}

}  // namespace zeroreg::open3d_module
