// A per-user cache of ONNX Runtime's optimised graphs (inference.graph_cache).
//
// Creating an ONNX Runtime session with ORT_ENABLE_ALL spends most of its time optimising the graph
// (fusions, constant folding, NCHWc layouts); the graph saved by an earlier process loads with
// optimisation off in a fraction of that time (docs/SPEED.md, "Start-up"). The saved graph is the
// same computation: XFeat's and YOLOX's outputs are bit-identical either way
// (tests/inference/graph_cache_test.cpp). Because the layout passes pick kernels for the CPU's
// vector extensions, an entry is keyed to the model's bytes, the ONNX Runtime version and the CPU
// (vendor, model and feature flags): another machine or runtime never reads it.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace zeroreg {

// The directory of the cache for a setting of inference.graph_cache: "off" gives nullopt; "auto"
// gives $ZEROREG_CACHE_DIR, else $XDG_CACHE_HOME/zeroreg, else $HOME/.cache/zeroreg (nullopt when
// none is set), each with "/onnxruntime-graphs" appended; any other value is that directory itself.
// Nothing is created here.
std::optional<std::string> GraphCacheDirectory(const std::string& setting);

// A description of this CPU for cache keys: the cpuid vendor, family / model / stepping and the
// feature words of leaves 1 and 7 (SSE .. AVX-512, AMX), plus the OS-enabled register state
// (XCR0). "unknown-cpu" where cpuid is not available.
std::string CpuSignature();

// One entry of the cache: where the optimised graph of a model file is (or will be) kept.
struct GraphCacheEntry {
  std::string graph_path;  // the optimised ONNX graph
  // Its check line, written after it: HMAC-SHA256 of the entry's key and the graph under a secret
  // of this user kept in the directory (.hmac-key-<uid>, mode 0600). A graph without a matching
  // check line is never loaded: a crash mid-write, another program's file, a graph altered by
  // anyone without the secret (a digest beside it is no proof: whoever alters the graph can
  // recompute it).
  std::string digest_path;
  std::string key;  // sha256 of (verified model sha256, runtime version, level, CPU), hex
};

// The entry for `model_path` in `directory`: the file name is the model's stem and the first 16
// hex digits of sha256(model's sha256, runtime_version, CpuSignature(), optimisation level).
// Throws InputError naming the model when it cannot be read.
GraphCacheEntry GraphCacheEntryFor(const std::string& directory, const std::string& model_path,
                                   const std::string& runtime_version);

// The entry's graph, read once, when it exists and its check line verifies under this user's
// secret; nullopt otherwise. The caller loads these very bytes (not the file again, which another
// process may have replaced meanwhile).
std::optional<std::vector<char>> ReadValidGraph(const GraphCacheEntry& entry);

// Whether ReadValidGraph would return the graph.
bool GraphCacheEntryValid(const GraphCacheEntry& entry);

// A fresh path beside the entry's graph for the runtime to write into (unique per process and
// call, so concurrent processes never write the same file). Creates the directory; nullopt when it
// cannot be created or written (a read-only home): the caller then runs without the cache.
std::optional<std::string> GraphCacheScratchPath(const GraphCacheEntry& entry);

// Moves a graph written at `scratch_path` into the entry (rename: readers see the old file or the
// new one, never half of one), then writes its digest the same way. Returns false, leaving no
// scratch file behind, when any step fails; the session already made is unaffected.
bool CommitGraphCacheEntry(const GraphCacheEntry& entry, const std::string& scratch_path);

}  // namespace zeroreg
