// Internals of the asset lookup (include/zeroreg/assets.hpp) exposed for the tests.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace zeroreg::detail {

// ResolveAssetsDir with its inputs passed in: `env_value` is the value of ZEROREG_ASSETS
// ("" = unset), `repo_dir` the repository root (the assets fallback is <repo_dir>/assets) and
// `installed_dirs` the installed share folders after it. Candidates are tried in that order; the
// first existing directory wins.
std::string ResolveAssetsDirFrom(const std::string& explicit_dir, const std::string& env_value,
                                 const std::string& repo_dir,
                                 const std::vector<std::string>& installed_dirs = {});

// <P>/share/zeroreg/assets for the nearest ancestor P of the folder of `binary_path` that has
// one (P/bin/zeroreg, P/lib/python3.11/site-packages/zeroreg/_zeroreg.so); when none has,
// <binary folder>/../share/zeroreg/assets, the place an install would have put it.
std::string InstalledAssetsDirFor(const std::string& binary_path);

// The file of the program or shared object this code was linked into (the CLI, a test binary,
// the Python extension): for a shared object the path the dynamic loader opened, for the main
// program /proc/self/exe (the loader's name for it is argv[0], which the caller chooses); "" if
// neither is known. What installed files are looked for beside (assets, the Open3D module).
std::string LoadedObjectPath();

// RequireAsset with the repository root passed in (its sha256 list is
// <repo_dir>/scripts/assets.sha256, with <assets_dir>/assets.sha256 as fallback).
std::string RequireAssetFrom(const std::string& assets_dir, const std::string& relative_path,
                             const std::string& repo_dir);

// Sha256OfFile, remembered for the process: a file whose device, inode, size, mtime and ctime
// are those it had when it was last hashed here is not read again (unless it was modified less
// than 2 s before that hashing: a change within one clock tick keeps the stamp). RequireAsset
// verifies a model with it, and the ONNX Runtime graph cache keys the same model by it (one read
// per model file and process instead of two).
std::string Sha256OfFileRemembered(const std::string& path);

// How many files Sha256OfFileRemembered (and so RequireAsset) has hashed in this process (cache
// misses only).
std::size_t AssetFilesHashedForTesting();

}  // namespace zeroreg::detail
