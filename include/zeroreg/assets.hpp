// Locating and verifying model files (DESIGN §5).
//
// Lookup order for the assets folder: explicit directory (config / --assets), then the
// ZEROREG_ASSETS environment variable, then <repo>/assets (the source tree the library was built
// from), then the installed share folder: P/share/zeroreg/assets for the nearest ancestor P of
// the running binary's folder that has one (the installed CLI in P/bin, the Python module in a
// venv or P/lib/pythonX.Y/site-packages), then <CMAKE_INSTALL_PREFIX>/share/zeroreg/assets of
// the build. An explicit directory that does not exist is an error (no fall-back to the
// others). Every model file is checked against the sha256 list kept in the repo
// (scripts/assets.sha256, or the copy installed beside the models) before it is loaded.
#pragma once

#include <string>

namespace zeroreg {

// Returns the assets folder to use; throws InputError naming every place that was tried when none
// exists, and how to fill it (scripts/fetch-assets.sh).
std::string ResolveAssetsDir(const std::string& explicit_dir);

// Returns the full path of `relative_path` (e.g. "xfeat/xfeat_640x640.onnx") inside the assets
// folder after checking that it exists and that its sha256 matches the repo's list. Throws
// InputError naming the file and the problem (missing, wrong checksum, not in the list) and the
// command that fixes it.
std::string RequireAsset(const std::string& assets_dir, const std::string& relative_path);

// SHA-256 of a file's bytes as 64 lowercase hex digits; throws InputError if unreadable.
std::string Sha256OfFile(const std::string& path);

}  // namespace zeroreg
