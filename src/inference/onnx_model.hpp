// One ONNX model run by one of two engines, ONNX Runtime or OpenCV DNN (inference.engine, issue
// 11). A model backend (XFeat, YOLOX, SAM, ...) prepares its input tensors and decodes the outputs
// itself; only the forward pass goes through here, so both engines share all pre- and
// post-processing and can be compared output for output (tests/inference).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"

namespace zeroreg {

enum class InferenceEngine { kOnnxRuntime, kOpenCv };

// "onnxruntime" / "opencv" (what `zeroreg info` reports).
std::string EngineName(InferenceEngine engine);

// Whether this build links ONNX Runtime (CMake ZEROREG_WITH_ONNXRUNTIME, docs/INSTALL.md).
bool OnnxRuntimeAvailable();

// The linked ONNX Runtime's version ("1.29.0"), or "" in a build without it.
std::string OnnxRuntimeVersion();

// The file the dynamic loader opened for the linked ONNX Runtime (libonnxruntime.so.1), or "" in
// a build without it or when the loader does not say: what a bug report needs to name.
std::string OnnxRuntimeLibraryPath();

// inference.engine resolved: "auto" is onnxruntime when available, else opencv. Throws InputError
// naming inference.engine for an unknown name, or for "onnxruntime" in a build without it, and
// naming inference.threads when it is outside 1..256 and inference.graph_cache when it is empty.
InferenceEngine ResolveEngine(const InferenceConfig& config);

// A float32 input: a name of the model's graph inputs, its shape and row-major data (not owned;
// must stay alive during Run).
struct TensorInput {
  std::string name;
  std::vector<std::int64_t> shape;
  const float* data = nullptr;
};

// A float32 output, owned.
struct Tensor {
  std::vector<std::int64_t> shape;
  std::vector<float> data;
};

class OnnxModel {
 public:
  virtual ~OnnxModel() = default;
  virtual InferenceEngine engine() const = 0;
  // Runs the model; returns the outputs named in `outputs`, in that order. Thread-safe (several
  // threads may call Run on one model). Throws InputError naming the model file when the run
  // fails (wrong input names or shapes, a missing output name).
  virtual std::vector<Tensor> Run(const std::vector<TensorInput>& inputs,
                                  const std::vector<std::string>& outputs) const = 0;
  // Names of the model's graph outputs, in the model's order (what Run accepts in `outputs`).
  virtual std::vector<std::string> OutputNames() const = 0;
  // Whether ONNX Runtime loaded the optimised graph from inference.graph_cache instead of
  // optimising the model file (always false for OpenCV DNN).
  virtual bool FromGraphCache() const { return false; }
};

// Loads the model at `path` for the engine of `config`. `what` names the model in errors
// ("XFeat ONNX model"). Throws InputError naming the file when it cannot be read or loaded.
std::unique_ptr<OnnxModel> LoadOnnxModel(const std::string& path, const std::string& what,
                                         const InferenceConfig& config);
// `graph_cache` is inference.graph_cache ("auto", "off" or a directory; ONNX Runtime only,
// src/inference/graph_cache.hpp).
std::unique_ptr<OnnxModel> LoadOnnxModel(const std::string& path, const std::string& what,
                                         InferenceEngine engine, int threads,
                                         const std::string& graph_cache = "off");

}  // namespace zeroreg
