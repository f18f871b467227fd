// Internals of the asset lookup (include/zeroreg/assets.hpp) exposed for the tests.
#pragma once

#include <cstddef>
#include <string>

namespace zeroreg::detail {

// ResolveAssetsDir with its three inputs passed in: `env_value` is the value of ZEROREG_ASSETS
// ("" = unset) and `repo_dir` the repository root (the assets fallback is <repo_dir>/assets).
// Candidates are tried in that order; the first existing directory wins.
std::string ResolveAssetsDirFrom(const std::string& explicit_dir, const std::string& env_value,
                                 const std::string& repo_dir);

// RequireAsset with the repository root passed in (its sha256 list is
// <repo_dir>/scripts/assets.sha256, with <assets_dir>/assets.sha256 as fallback).
std::string RequireAssetFrom(const std::string& assets_dir, const std::string& relative_path,
                             const std::string& repo_dir);

// How many files RequireAsset has hashed in this process (cache misses only).
std::size_t AssetFilesHashedForTesting();

}  // namespace zeroreg::detail
