#include "inference/onnx_model.hpp"

#include <filesystem>
#include <fstream>
#include <mutex>
#include <numeric>
#include <opencv2/dnn.hpp>
#include <optional>

#include "inference/graph_cache.hpp"
#include "zeroreg/error.hpp"

#ifdef ZEROREG_WITH_ONNXRUNTIME
#include <dlfcn.h>
#include <onnxruntime_cxx_api.h>
#endif

namespace zeroreg {
namespace {

void RequireReadable(const std::string& path, const std::string& what) {
  if (path.empty()) throw MakeInputError(what, "no model file given");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MakeInputError(path, "cannot open the " + what);
}

// ---------------------------------------------------------------------------------------------

class OpenCvModel : public OnnxModel {
 public:
  OpenCvModel(const std::string& path, const std::string& what) : path_(path), what_(what) {
    try {
      net_ = cv::dnn::readNetFromONNX(path);
    } catch (const cv::Exception& e) {
      throw MakeInputError(path, "cannot load the " + what + " with OpenCV DNN (" + e.what() +
                                     "); inference.engine=onnxruntime may load it");
    }
    if (net_.empty()) throw MakeInputError(path, "the " + what + " loaded empty in OpenCV DNN");
    net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  }
  InferenceEngine engine() const override { return InferenceEngine::kOpenCv; }

  std::vector<Tensor> Run(const std::vector<TensorInput>& inputs,
                          const std::vector<std::string>& outputs) const override {
    std::vector<cv::Mat> results;
    try {
      // cv::dnn::Net::forward is not re-entrant, and its outputs share the net's buffers.
      std::lock_guard<std::mutex> lock(mutex_);
      for (const TensorInput& input : inputs) {
        std::vector<int> dims(input.shape.begin(), input.shape.end());
        // setInput keeps a reference; the caller's data outlives the forward pass below.
        const cv::Mat blob(static_cast<int>(dims.size()), dims.data(), CV_32F,
                           const_cast<float*>(input.data));
        net_.setInput(blob, input.name);
      }
      net_.forward(results, std::vector<cv::String>(outputs.begin(), outputs.end()));
    } catch (const cv::Exception& e) {
      throw MakeInputError(path_,
                           "OpenCV DNN forward pass of the " + what_ + " failed: " + e.what());
    }
    std::vector<Tensor> out(results.size());
    for (size_t i = 0; i < results.size(); ++i) {
      const cv::Mat& m = results[i];
      if (m.type() != CV_32F) {
        throw MakeInputError(path_,
                             "output '" + outputs[i] + "' of the " + what_ + " is not float32");
      }
      for (int d = 0; d < m.dims; ++d) out[i].shape.push_back(m.size[d]);
      const cv::Mat contiguous = m.isContinuous() ? m : m.clone();
      const float* p = contiguous.ptr<float>();
      out[i].data.assign(p, p + contiguous.total());
    }
    return out;
  }

  std::vector<std::string> OutputNames() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::vector<cv::String> names = net_.getUnconnectedOutLayersNames();
    return std::vector<std::string>(names.begin(), names.end());
  }

 private:
  std::string path_, what_;
  mutable cv::dnn::Net net_;
  mutable std::mutex mutex_;
};

// ---------------------------------------------------------------------------------------------

#ifdef ZEROREG_WITH_ONNXRUNTIME

size_t Count(const std::vector<std::int64_t>& shape) {
  return std::accumulate(shape.begin(), shape.end(), size_t{1},
                         [](size_t a, std::int64_t b) { return a * static_cast<size_t>(b); });
}

// One environment per process (ORT's logging and default thread state); created on first use and
// never destroyed: sessions held by other static objects may outlive any static destructor order.
Ort::Env& Environment() {
  static Ort::Env* env = new Ort::Env(ORT_LOGGING_LEVEL_ERROR, "zeroreg");
  return *env;
}

// The options of every session: `level` ORT_ENABLE_ALL for a model file, ORT_DISABLE_ALL for a
// graph the cache holds (optimised already); `save_as`, when given, is where ONNX Runtime writes
// the optimised graph.
Ort::SessionOptions SessionOptions(int threads, GraphOptimizationLevel level,
                                   const std::string& save_as = "") {
  Ort::SessionOptions options;
  options.SetIntraOpNumThreads(threads);
  options.SetInterOpNumThreads(1);
  options.SetExecutionMode(ORT_SEQUENTIAL);
  options.SetGraphOptimizationLevel(level);
  // Idle pool threads sleep instead of spinning: the machine is shared (eval --jobs runs one
  // model per job) and a spinning pool takes the cores other jobs need.
  options.AddConfigEntry("session.intra_op.allow_spinning", "0");
  options.SetDeterministicCompute(true);
  if (!save_as.empty()) options.SetOptimizedModelFilePath(save_as.c_str());
  return options;
}

class OrtModel : public OnnxModel {
 public:
  OrtModel(const std::string& path, const std::string& what, int threads,
           const std::string& graph_cache)
      : path_(path), what_(what) {
    std::optional<GraphCacheEntry> entry;
    if (const std::optional<std::string> directory = GraphCacheDirectory(graph_cache)) {
      entry = GraphCacheEntryFor(*directory, path, OnnxRuntimeVersion());
    }
    const std::optional<std::vector<char>> cached = entry ? ReadValidGraph(*entry) : std::nullopt;
    if (cached) {
      try {
        session_ = std::make_unique<Ort::Session>(Environment(), cached->data(), cached->size(),
                                                  SessionOptions(threads, ORT_DISABLE_ALL));
        from_graph_cache_ = true;
        return;
      } catch (const Ort::Exception&) {
        // Not loadable after all (a graph of another build of the same version): optimise anew,
        // which replaces it below.
      }
    }
    std::optional<std::string> scratch = entry ? GraphCacheScratchPath(*entry) : std::nullopt;
    try {
      session_ = std::make_unique<Ort::Session>(
          Environment(), path.c_str(),
          SessionOptions(threads, ORT_ENABLE_ALL, scratch ? *scratch : std::string()));
    } catch (const Ort::Exception& e) {
      if (!scratch) {
        throw MakeInputError(path, "cannot load the " + what + " with ONNX Runtime: " + e.what());
      }
      // Perhaps only the saving failed: once more without it, which names the model if it fails.
      std::error_code ignored;
      std::filesystem::remove(*scratch, ignored);
      scratch.reset();
      try {
        session_ = std::make_unique<Ort::Session>(Environment(), path.c_str(),
                                                  SessionOptions(threads, ORT_ENABLE_ALL));
      } catch (const Ort::Exception& again) {
        throw MakeInputError(path,
                             "cannot load the " + what + " with ONNX Runtime: " + again.what());
      }
    }
    if (scratch) CommitGraphCacheEntry(*entry, *scratch);
  }
  InferenceEngine engine() const override { return InferenceEngine::kOnnxRuntime; }

  std::vector<Tensor> Run(const std::vector<TensorInput>& inputs,
                          const std::vector<std::string>& outputs) const override {
    try {
      const Ort::MemoryInfo memory =
          Ort::MemoryInfo::CreateCpu(OrtArenaAllocator, OrtMemTypeDefault);
      std::vector<Ort::Value> values;
      std::vector<const char*> input_names, output_names;
      for (const TensorInput& input : inputs) {
        // ORT reads the caller's buffer in place (no copy); the API takes non-const data.
        values.push_back(Ort::Value::CreateTensor<float>(memory, const_cast<float*>(input.data),
                                                         Count(input.shape), input.shape.data(),
                                                         input.shape.size()));
        input_names.push_back(input.name.c_str());
      }
      for (const std::string& name : outputs) output_names.push_back(name.c_str());
      // Session::Run is thread-safe: no lock.
      std::vector<Ort::Value> results =
          session_->Run(Ort::RunOptions{nullptr}, input_names.data(), values.data(), values.size(),
                        output_names.data(), output_names.size());
      std::vector<Tensor> out(results.size());
      for (size_t i = 0; i < results.size(); ++i) {
        const auto info = results[i].GetTensorTypeAndShapeInfo();
        if (info.GetElementType() != ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT) {
          throw MakeInputError(path_,
                               "output '" + outputs[i] + "' of the " + what_ + " is not float32");
        }
        out[i].shape = info.GetShape();
        const float* p = results[i].GetTensorData<float>();
        out[i].data.assign(p, p + info.GetElementCount());
      }
      return out;
    } catch (const Ort::Exception& e) {
      throw MakeInputError(path_, "ONNX Runtime run of the " + what_ + " failed: " + e.what());
    }
  }

  std::vector<std::string> OutputNames() const override {
    Ort::AllocatorWithDefaultOptions allocator;
    std::vector<std::string> names;
    for (size_t i = 0; i < session_->GetOutputCount(); ++i) {
      names.emplace_back(session_->GetOutputNameAllocated(i, allocator).get());
    }
    return names;
  }

  bool FromGraphCache() const override { return from_graph_cache_; }

 private:
  std::string path_, what_;
  std::unique_ptr<Ort::Session> session_;
  bool from_graph_cache_ = false;
};

#endif  // ZEROREG_WITH_ONNXRUNTIME

}  // namespace

std::string EngineName(InferenceEngine engine) {
  return engine == InferenceEngine::kOnnxRuntime ? "onnxruntime" : "opencv";
}

bool OnnxRuntimeAvailable() {
#ifdef ZEROREG_WITH_ONNXRUNTIME
  return true;
#else
  return false;
#endif
}

std::string OnnxRuntimeVersion() {
#ifdef ZEROREG_WITH_ONNXRUNTIME
  return OrtGetApiBase()->GetVersionString();
#else
  return "";
#endif
}

std::string OnnxRuntimeLibraryPath() {
#ifdef ZEROREG_WITH_ONNXRUNTIME
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&OrtGetApiBase), &info) != 0 &&
      info.dli_fname != nullptr) {
    std::error_code error;
    const std::filesystem::path path = std::filesystem::canonical(info.dli_fname, error);
    return error ? std::string(info.dli_fname) : path.string();
  }
#endif
  return "";
}

InferenceEngine ResolveEngine(const InferenceConfig& config) {
  if (config.threads < 1 || config.threads > 256) {
    throw MakeInputError("inference.threads",
                         "is " + std::to_string(config.threads) + ", expected 1..256");
  }
  if (config.graph_cache.empty()) {
    throw MakeInputError("inference.graph_cache",
                         "is empty, expected \"auto\", \"off\" or a directory");
  }
  if (config.engine == "auto") {
    return OnnxRuntimeAvailable() ? InferenceEngine::kOnnxRuntime : InferenceEngine::kOpenCv;
  }
  if (config.engine == "opencv") return InferenceEngine::kOpenCv;
  if (config.engine == "onnxruntime") {
    if (!OnnxRuntimeAvailable()) {
      throw MakeInputError("inference.engine",
                           "is \"onnxruntime\" but this zeroreg was built without ONNX Runtime "
                           "(CMake ZEROREG_WITH_ONNXRUNTIME); available: opencv (docs/INSTALL.md: "
                           "bash scripts/install-onnxruntime.sh, then rebuild)");
    }
    return InferenceEngine::kOnnxRuntime;
  }
  throw MakeInputError("inference.engine", "unknown engine '" + config.engine +
                                               "', expected one of: auto, onnxruntime, opencv");
}

std::unique_ptr<OnnxModel> LoadOnnxModel(const std::string& path, const std::string& what,
                                         const InferenceConfig& config) {
  return LoadOnnxModel(path, what, ResolveEngine(config), config.threads, config.graph_cache);
}

std::unique_ptr<OnnxModel> LoadOnnxModel(const std::string& path, const std::string& what,
                                         InferenceEngine engine, int threads,
                                         const std::string& graph_cache) {
  RequireReadable(path, what);
  if (engine == InferenceEngine::kOpenCv) return std::make_unique<OpenCvModel>(path, what);
#ifdef ZEROREG_WITH_ONNXRUNTIME
  return std::make_unique<OrtModel>(path, what, threads, graph_cache);
#else
  (void)threads;
  (void)graph_cache;
  throw MakeInputError(path, "the " + what + " needs ONNX Runtime, which this build lacks");
#endif
}

}  // namespace zeroreg
