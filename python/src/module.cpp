// The compiled part of the Python module `zeroreg` (imported as zeroreg._zeroreg; the public API
// and the Scan/View classes are in python/zeroreg/__init__.py, see docs/PYTHON.md).
//
// Everything that crosses the boundary is checked here, and every problem is raised as ValueError
// whose message starts with the offending argument, e.g. "source.views[0].depth: ...": arrays
// coming from Python are untrusted input just like files (common rule: errors at input
// boundaries name the argument, what was wrong and what was expected).
//
// Conventions at the boundary (documented in docs/PYTHON.md):
// - colour is RGB (HxWx3 uint8) in Python, BGR in C++ (View::color);
// - depth is uint16 raw units with depth_scale (raw per metre; 0 and 65535 invalid, as in
//   ReadDepthImage) or float32 metres (0 invalid);
// - transforms are 4x4 float64, named T_to_from as in types.hpp.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include "verify/verify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "estimate/depth_noise.hpp"
#include "estimate/icp.hpp"
#include "eval/metrics.hpp"
#include "io/image_checks.hpp"
#include "io/image_file.hpp"
#include "open3d_module/open3d_module.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/recordings.hpp"
#include "zeroreg/register.hpp"
#include "zeroreg/version.hpp"

namespace py = pybind11;
using nlohmann::json;

namespace zeroreg::python {
namespace {

// ---- Python <-> JSON (config dicts, to_dict) ---------------------------------------------------

json ToJson(const py::handle& obj, const std::string& where) {
  if (obj.is_none()) return nullptr;
  // numpy scalars and arrays (np.float64(0.1), np.int64(5), np.array([...])) become plain Python
  // values first, so that configs built with numpy arithmetic work.
  const py::module_ numpy = py::module_::import("numpy");
  if (py::isinstance(obj, numpy.attr("generic")) || py::isinstance<py::array>(obj)) {
    return ToJson(obj.attr("tolist")(), where);
  }
  if (py::isinstance<py::bool_>(obj)) return obj.cast<bool>();  // before int: bool is an int
  if (py::isinstance<py::int_>(obj)) {
    try {
      return obj.cast<std::int64_t>();
    } catch (const py::cast_error&) {
    }
    try {
      return obj.cast<std::uint64_t>();
    } catch (const py::cast_error&) {
    }
    throw MakeInputError(
        where, "integer " + py::str(obj).cast<std::string>() + " does not fit in 64 bits");
  }
  if (py::isinstance<py::float_>(obj)) return obj.cast<double>();
  if (py::isinstance<py::str>(obj)) return obj.cast<std::string>();
  if (py::isinstance<py::dict>(obj)) {
    json out = json::object();
    for (const auto& item : obj.cast<py::dict>()) {
      if (!py::isinstance<py::str>(item.first)) {
        throw MakeInputError(where, "key " + py::repr(item.first).cast<std::string>() +
                                        " is not a string; expected string keys");
      }
      const std::string key = item.first.cast<std::string>();
      out[key] = ToJson(item.second, where + "." + key);
    }
    return out;
  }
  if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
    json out = json::array();
    size_t i = 0;
    for (const py::handle& item : obj) {
      out.push_back(ToJson(item, where + "[" + std::to_string(i++) + "]"));
    }
    return out;
  }
  throw MakeInputError(where, "cannot use a value of type " +
                                  py::str(py::type::of(obj).attr("__name__")).cast<std::string>() +
                                  "; expected None, bool, int, float, str, list or dict");
}

py::object FromJson(const json& j) {
  switch (j.type()) {
    case json::value_t::null:
      return py::none();
    case json::value_t::boolean:
      return py::bool_(j.get<bool>());
    case json::value_t::number_integer:
      return py::int_(j.get<std::int64_t>());
    case json::value_t::number_unsigned:
      return py::int_(j.get<std::uint64_t>());
    case json::value_t::number_float:
      return py::float_(j.get<double>());
    case json::value_t::string:
      return py::str(j.get<std::string>());
    case json::value_t::array: {
      py::list out;
      for (const json& item : j) out.append(FromJson(item));
      return std::move(out);
    }
    case json::value_t::object: {
      py::dict out;
      for (auto it = j.begin(); it != j.end(); ++it) out[py::str(it.key())] = FromJson(it.value());
      return std::move(out);
    }
    default:
      return py::none();  // binary / discarded values are never produced by zeroreg
  }
}

std::string TypeName(const py::handle& obj);

// A file-system path from Python (str, bytes or os.PathLike) as the bytes the OS uses: os.fsencode
// turns the surrogate escapes Python uses for a non-UTF-8 file name back into its bytes.
std::string PathFromPython(const py::handle& obj, const std::string& where) {
  py::object encoded;
  try {
    encoded = py::module_::import("os").attr("fsencode")(obj);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_TypeError)) {
      throw py::type_error(where + ": got " + TypeName(obj) +
                           "; expected a path (str, bytes or os.PathLike)");
    }
    throw py::value_error(where + ": cannot be used as a file name (" +
                          py::str(e.value()).cast<std::string>() + ")");
  }
  return encoded.cast<std::string>();
}

bool IsPath(const py::handle& obj) {
  return py::isinstance<py::str>(obj) || py::isinstance<py::bytes>(obj) ||
         py::hasattr(obj, "__fspath__");
}

// Text made from file names (scan and view names) as a Python str: bytes that are not UTF-8 come
// back as surrogate escapes, exactly as os.fsdecode gives them, instead of failing the call.
py::str TextToPython(const std::string& text) {
  PyObject* decoded =
      PyUnicode_DecodeFSDefaultAndSize(text.data(), static_cast<Py_ssize_t>(text.size()));
  if (decoded == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(decoded);
}

// config: None (defaults), a dict with the JSON config's keys, or a path to a JSON config file.
// seed: None (keep the config's) or a non-negative int that overrides config["seed"].
PipelineConfig ConfigFromPython(const py::object& config, const py::object& seed) {
  PipelineConfig out;
  if (config.is_none()) {
    // defaults
  } else if (py::isinstance<py::dict>(config)) {
    ApplyConfigJson(ToJson(config, "config"), "config", &out);
  } else if (IsPath(config)) {  // str, bytes or os.PathLike: a JSON file
    out = ReadConfigFile(PathFromPython(config, "config"));
  } else {
    throw MakeInputError("config", "expected None, a dict or the path of a JSON config file");
  }
  if (!seed.is_none()) {
    if (!py::isinstance<py::int_>(seed) || py::isinstance<py::bool_>(seed)) {
      throw MakeInputError("seed", "expected a non-negative int or None");
    }
    try {
      out.seed = seed.cast<std::uint64_t>();
    } catch (const py::cast_error&) {
      throw MakeInputError(
          "seed", py::str(seed).cast<std::string>() + " is not a non-negative 64-bit integer");
    }
  }
  return out;
}

// ---- arrays ------------------------------------------------------------------------------------

std::string ShapeString(const py::array& a) {
  std::ostringstream s;
  s << "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

std::string DtypeName(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

std::string TypeName(const py::handle& obj) {
  return py::str(py::type::of(obj).attr("__name__")).cast<std::string>();
}

// The object as a numpy array without any conversion (images must already have the right dtype:
// silently casting float colour to uint8 would hide a real mistake).
py::array RequireNdarray(const py::handle& obj, const std::string& where,
                         const std::string& expected) {
  if (!py::isinstance<py::array>(obj)) {
    throw MakeInputError(where, "got " + TypeName(obj) + "; expected a numpy array " + expected);
  }
  return py::reinterpret_borrow<py::array>(obj);
}

// Any array-like of numbers (list of lists, numpy array of any numeric dtype) as float64 with the
// given shape; rows == -1 accepts any number of rows. Non-finite values are an error.
py::array_t<double, py::array::c_style> RequireFloatMatrix(const py::handle& obj,
                                                           const std::string& where,
                                                           py::ssize_t rows, py::ssize_t cols,
                                                           const std::string& what) {
  const std::string expected =
      (rows < 0 ? "(N, " : "(" + std::to_string(rows) + ", ") + std::to_string(cols) + ")";
  py::array a;
  if (py::isinstance<py::array>(obj)) {
    a = py::reinterpret_borrow<py::array>(obj);
  } else {
    try {
      a = py::module_::import("numpy").attr("asarray")(obj);
    } catch (const py::error_already_set&) {
      throw MakeInputError(where, "cannot be read as an array; expected " + what + " " + expected);
    }
  }
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw MakeInputError(where,
                         "dtype " + DtypeName(a) + "; expected numbers, " + what + " " + expected);
  }
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || a.shape(1) != cols) {
    throw MakeInputError(where, "shape " + ShapeString(a) + "; expected " + what + " " + expected);
  }
  auto out = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!out) throw MakeInputError(where, "cannot be converted to float64");
  const double* p = out.data();
  for (py::ssize_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(p[i])) {
      const py::ssize_t r = i / cols, c = i % cols;
      throw MakeInputError(where, "element [" + std::to_string(r) + ", " + std::to_string(c) +
                                      "] is " + (std::isnan(p[i]) ? "NaN" : "infinite") +
                                      "; expected finite numbers");
    }
  }
  return out;
}

// A 4x4 rigid transform: last row 0 0 0 1, orthonormal rotation with det +1 (the tolerance of
// ReadPoseFile, 1e-2, so that a pose read from text and one given as an array are held to the same
// standard).
Transform RequireRigid(const py::handle& obj, const std::string& where) {
  const auto a = RequireFloatMatrix(obj, where, 4, 4, "rigid transform");
  Transform T;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) T(r, c) = a.at(r, c);
  }
  if (std::abs(T(3, 0)) > 1e-9 || std::abs(T(3, 1)) > 1e-9 || std::abs(T(3, 2)) > 1e-9 ||
      std::abs(T(3, 3) - 1.0) > 1e-9) {
    std::ostringstream s;
    s << "last row is [" << T(3, 0) << ", " << T(3, 1) << ", " << T(3, 2) << ", " << T(3, 3)
      << "]; expected [0, 0, 0, 1] (a rigid 4x4 transform)";
    throw MakeInputError(where, s.str());
  }
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double orthonormality_error =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality_error > 1e-2 || R.determinant() <= 0.0) {
    std::ostringstream s;
    s << "rotation is not rigid (max |R^T R - I| = " << orthonormality_error
      << ", det R = " << R.determinant()
      << "); expected an orthonormal rotation with det +1 (tolerance 1e-2)";
    throw MakeInputError(where, s.str());
  }
  return T;
}

// 3x3 pinhole camera matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]; Intrinsics has no skew.
Intrinsics RequireIntrinsics(const py::handle& obj, const std::string& where, int width,
                             int height) {
  const auto K = RequireFloatMatrix(obj, where, 3, 3, "camera matrix");
  if (std::abs(K.at(0, 1)) > 1e-9 || std::abs(K.at(1, 0)) > 1e-9 || std::abs(K.at(2, 0)) > 1e-9 ||
      std::abs(K.at(2, 1)) > 1e-9 || std::abs(K.at(2, 2) - 1.0) > 1e-9) {
    throw MakeInputError(where,
                         "not a pinhole camera matrix; expected [[fx, 0, cx], [0, fy, cy], [0, 0, "
                         "1]] (no skew)");
  }
  Intrinsics k;
  k.fx = K.at(0, 0);
  k.fy = K.at(1, 1);
  k.cx = K.at(0, 2);
  k.cy = K.at(1, 2);
  k.width = width;
  k.height = height;
  detail::CheckIntrinsics(k, where);  // the same plausibility rules as files
  return k;
}

// The image limit of files (ZEROREG_MAX_IMAGE_PIXELS) for an array, checked before any copy.
void RequireImageSize(const py::array& a, const std::string& where) {
  const std::uint64_t limit = detail::MaxImagePixels();
  const auto pixels =
      static_cast<std::uint64_t>(a.shape(0)) * static_cast<std::uint64_t>(a.shape(1));
  if (pixels > limit) {
    throw MakeInputError(where, "shape " + ShapeString(a) + " is " + std::to_string(pixels) +
                                    " pixels, more than the limit of " + std::to_string(limit) +
                                    " (set ZEROREG_MAX_IMAGE_PIXELS to raise it)");
  }
}

// RGB HxWx3 uint8 -> BGR CV_8UC3 (a copy: the View owns its pixels).
cv::Mat ColorFromPython(const py::handle& obj, const std::string& where) {
  const std::string expected = "of dtype uint8 with shape (H, W, 3), RGB";
  const py::array a = RequireNdarray(obj, where, expected);
  if (a.dtype().kind() != 'u' || a.itemsize() != 1) {
    throw MakeInputError(where, "dtype " + DtypeName(a) + "; expected " + expected.substr(3));
  }
  if (a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) == 0 || a.shape(1) == 0) {
    throw MakeInputError(where, "shape " + ShapeString(a) + "; expected (H, W, 3) uint8 RGB");
  }
  RequireImageSize(a, where);
  const auto c = py::array_t<std::uint8_t, py::array::c_style>::ensure(a);
  const cv::Mat rgb(static_cast<int>(c.shape(0)), static_cast<int>(c.shape(1)), CV_8UC3,
                    const_cast<std::uint8_t*>(c.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

// uint16 raw + depth_scale, or float32 metres -> CV_32FC1 metres, 0 = invalid.
cv::Mat DepthFromPython(const py::handle& obj, const py::handle& depth_scale_obj,
                        const std::string& where, const std::string& scale_where,
                        const std::string& color_shape, int height, int width) {
  const std::string expected = "of shape (H, W): uint16 with depth_scale, or float32 metres";
  const py::array a = RequireNdarray(obj, where, expected);
  const bool is_u16 = a.dtype().kind() == 'u' && a.itemsize() == 2;
  const bool is_f32 = a.dtype().kind() == 'f' && a.itemsize() == 4;
  if (!is_u16 && !is_f32) {
    throw MakeInputError(where, "dtype " + DtypeName(a) +
                                    "; expected uint16 (with depth_scale) or float32 (metres)");
  }
  if (a.ndim() != 2) {
    throw MakeInputError(where, "shape " + ShapeString(a) + "; expected (H, W)");
  }
  if (a.shape(0) != height || a.shape(1) != width) {
    throw MakeInputError(where,
                         "shape " + ShapeString(a) + " does not match colour " + color_shape);
  }
  cv::Mat metres(height, width, CV_32FC1);
  if (is_u16) {
    if (depth_scale_obj.is_none()) {
      throw MakeInputError(scale_where,
                           "missing; uint16 depth needs depth_scale (raw units per metre, e.g. "
                           "1000 for millimetres, 5000 for TUM)");
    }
    double scale = 0;
    try {
      scale = depth_scale_obj.cast<double>();
    } catch (const py::cast_error&) {
      throw MakeInputError(scale_where, "got " + TypeName(depth_scale_obj) +
                                            "; expected a positive number (raw units per metre)");
    }
    if (!std::isfinite(scale) || scale <= 0) {
      throw MakeInputError(scale_where, "is " + py::str(depth_scale_obj).cast<std::string>() +
                                            "; expected a positive number (raw units per metre)");
    }
    const auto d = py::array_t<std::uint16_t, py::array::c_style>::ensure(a);
    for (int r = 0; r < height; ++r) {
      const std::uint16_t* src = d.data() + static_cast<std::ptrdiff_t>(r) * width;
      float* dst = metres.ptr<float>(r);
      for (int c = 0; c < width; ++c) {
        // Same conversion as ReadDepthImage: 0 = no measurement, 65535 = saturated / invalid.
        dst[c] = (src[c] == 0 || src[c] == 65535) ? 0.0f : static_cast<float>(src[c] / scale);
      }
    }
  } else {
    if (!depth_scale_obj.is_none()) {
      throw MakeInputError(scale_where,
                           "given for float32 depth; float32 depth is already in metres (pass "
                           "depth_scale only with uint16 depth)");
    }
    const auto d = py::array_t<float, py::array::c_style>::ensure(a);
    for (int r = 0; r < height; ++r) {
      const float* src = d.data() + static_cast<std::ptrdiff_t>(r) * width;
      float* dst = metres.ptr<float>(r);
      for (int c = 0; c < width; ++c) {
        if (!std::isfinite(src[c]) || src[c] < 0.0f) {
          std::ostringstream s;
          s << "value " << src[c] << " at pixel (row " << r << ", col " << c
            << "); expected finite metres >= 0 (0 = no measurement)";
          throw MakeInputError(where, s.str());
        }
        dst[c] = src[c];
      }
    }
  }
  if (cv::countNonZero(metres > 0.0f) == 0) {
    throw MakeInputError(where, "has no valid pixel (all 0 or 65535); expected some depth");
  }
  detail::CheckDepthRange(metres, where, scale_where, is_u16 ? depth_scale_obj.cast<double>() : 0);
  return metres;
}

// Reads the keys of a dict, remembering which were used, so that a misspelt key ("pose" for
// "T_scan_camera") is an error rather than silently ignored. None counts as absent.
class DictReader {
 public:
  DictReader(const py::handle& obj, std::string where) : where_(std::move(where)) {
    if (!py::isinstance<py::dict>(obj)) {
      throw MakeInputError(where_, "got " + TypeName(obj) + "; expected a dict");
    }
    dict_ = py::reinterpret_borrow<py::dict>(obj);
  }
  py::object Get(const char* key) {
    known_.push_back(key);
    return dict_.contains(key) ? py::object(dict_[key]) : py::object(py::none());
  }
  py::object Require(const char* key, const std::string& expected) {
    py::object value = Get(key);
    if (value.is_none()) throw MakeInputError(where_ + "." + key, "missing; expected " + expected);
    return value;
  }
  std::string GetString(const char* key, const std::string& fallback) {
    const py::object value = Get(key);
    if (value.is_none()) return fallback;
    if (!py::isinstance<py::str>(value)) {
      throw MakeInputError(where_ + "." + key, "got " + TypeName(value) + "; expected a str");
    }
    return value.cast<std::string>();
  }
  void Finish() const {
    for (const auto& item : dict_) {
      const std::string key = py::str(item.first).cast<std::string>();
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        std::string known;
        for (const std::string& k : known_) known += (known.empty() ? "" : ", ") + k;
        throw MakeInputError(where_, "unknown key '" + key + "'; known keys: " + known);
      }
    }
  }

 private:
  py::dict dict_;
  std::string where_;
  std::vector<std::string> known_;
};

View ViewFromPython(const py::handle& obj, const std::string& where, const std::string& name) {
  DictReader d(obj, where);
  View view;
  view.name = d.GetString("name", name);
  view.color =
      ColorFromPython(d.Require("color", "an (H, W, 3) uint8 RGB array"), where + ".color");
  const std::string color_shape =
      "(" + std::to_string(view.color.rows) + ", " + std::to_string(view.color.cols) + ")";
  const py::object depth = d.Require("depth", "an (H, W) uint16 or float32 array");
  view.depth =
      DepthFromPython(depth, d.Get("depth_scale"), where + ".depth", where + ".depth_scale",
                      color_shape, view.color.rows, view.color.cols);
  view.intrinsics = RequireIntrinsics(d.Require("intrinsics", "a 3x3 camera matrix"),
                                      where + ".intrinsics", view.color.cols, view.color.rows);
  const py::object pose = d.Get("T_scan_camera");
  if (!pose.is_none()) view.T_scan_camera = RequireRigid(pose, where + ".T_scan_camera");
  const py::object gt = d.Get("T_world_camera_gt");
  if (!gt.is_none()) view.T_world_camera_gt = RequireRigid(gt, where + ".T_world_camera_gt");
  d.Finish();
  return view;
}

std::vector<Eigen::Vector3d> PointsFromPython(const py::handle& obj, const std::string& where,
                                              const std::string& what) {
  const auto a = RequireFloatMatrix(obj, where, -1, 3, what);
  std::vector<Eigen::Vector3d> out(static_cast<size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[i] = {a.at(i, 0), a.at(i, 1), a.at(i, 2)};
  return out;
}

// A scan given as a dict (python/zeroreg/__init__.py turns zeroreg.Scan / zeroreg.View objects
// into dicts before calling in) or as a path specification for LoadScan.
Scan ScanFromPython(const py::handle& obj, const std::string& where) {
  if (IsPath(obj)) return LoadScan(PathFromPython(obj, where));
  DictReader d(obj, where);
  Scan scan;
  scan.name = d.GetString("name", where);
  const py::object views = d.Require("views", "a list of views");
  if (!py::isinstance<py::list>(views) && !py::isinstance<py::tuple>(views)) {
    throw MakeInputError(where + ".views",
                         "got " + TypeName(views) + "; expected a list of views (dicts)");
  }
  const size_t max_views = detail::MaxViewsPerScan();
  if (py::len(views) > max_views) {
    throw MakeInputError(where + ".views", "holds " + std::to_string(py::len(views)) +
                                               " views, more than the limit of " +
                                               std::to_string(max_views) +
                                               " per scan (set ZEROREG_MAX_VIEWS to raise it)");
  }
  size_t i = 0;
  for (const py::handle& v : views) {
    const std::string view_where = where + ".views[" + std::to_string(i) + "]";
    scan.views.push_back(ViewFromPython(v, view_where, "view " + std::to_string(i)));
    ++i;
  }
  if (scan.views.empty()) {
    throw MakeInputError(where + ".views", "is empty; expected at least one view");
  }
  const py::object points = d.Get("points");
  if (!points.is_none()) {
    scan.points = PointsFromPython(points, where + ".points", "points in metres");
  }
  const py::object colors = d.Get("colors");
  if (!colors.is_none()) {
    scan.colors = PointsFromPython(colors, where + ".colors", "RGB colours in [0, 1]");
    if (scan.colors.size() != scan.points.size()) {
      throw MakeInputError(where + ".colors", std::to_string(scan.colors.size()) + " colours for " +
                                                  std::to_string(scan.points.size()) +
                                                  " points; expected one colour per point");
    }
    for (const Eigen::Vector3d& c : scan.colors) {
      if (c.minCoeff() < 0 || c.maxCoeff() > 1) {
        throw MakeInputError(where + ".colors", "value outside [0, 1]; expected RGB in [0, 1]");
      }
    }
  }
  const py::object gt = d.Get("T_world_scan_gt");
  if (!gt.is_none()) scan.T_world_scan_gt = RequireRigid(gt, where + ".T_world_scan_gt");
  d.Finish();
  return scan;
}

// ---- C++ -> numpy --------------------------------------------------------------------------

py::array_t<double> MatrixToNumpy(const Eigen::MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) w(r, c) = m(r, c);
  }
  return out;
}

py::object OptionalTransform(const std::optional<Transform>& T) {
  return T ? py::object(MatrixToNumpy(*T)) : py::object(py::none());
}

py::array_t<double> PointsToNumpy(const std::vector<Eigen::Vector3d>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto w = out.mutable_unchecked<2>();
  for (size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) w(i, k) = points[i][k];
  }
  return out;
}

py::array_t<std::uint8_t> ColorToNumpy(const cv::Mat& bgr) {
  py::array_t<std::uint8_t> out({bgr.rows, bgr.cols, 3});
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, out.mutable_data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return out;
}

py::array_t<float> DepthToNumpy(const cv::Mat& depth) {
  py::array_t<float> out({depth.rows, depth.cols});
  cv::Mat view(depth.rows, depth.cols, CV_32FC1, out.mutable_data());
  depth.copyTo(view);
  return out;
}

py::dict ViewToPython(const View& v) {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = v.intrinsics.fx;
  K(1, 1) = v.intrinsics.fy;
  K(0, 2) = v.intrinsics.cx;
  K(1, 2) = v.intrinsics.cy;
  py::dict d;
  d["name"] = TextToPython(v.name);
  d["color"] = ColorToNumpy(v.color);
  d["depth"] = DepthToNumpy(v.depth);
  d["intrinsics"] = MatrixToNumpy(K);
  d["T_scan_camera"] = MatrixToNumpy(v.T_scan_camera);
  d["T_world_camera_gt"] = OptionalTransform(v.T_world_camera_gt);
  return d;
}

py::dict ScanToPython(const Scan& scan) {
  py::list views;
  for (const View& v : scan.views) views.append(ViewToPython(v));
  py::dict d;
  d["name"] = TextToPython(scan.name);
  d["views"] = views;
  d["points"] = scan.points.empty() ? py::object(py::none()) : PointsToNumpy(scan.points);
  d["colors"] = scan.colors.empty() ? py::object(py::none()) : PointsToNumpy(scan.colors);
  d["T_world_scan_gt"] = OptionalTransform(scan.T_world_scan_gt);
  return d;
}

// Result arrays, one row per correspondence (all parallel to RegistrationResult::correspondences).
template <typename T, typename Fill>
py::array_t<T> CorrespondenceColumn(const RegistrationResult& r, py::ssize_t cols, Fill fill) {
  const auto n = static_cast<py::ssize_t>(r.correspondences.size());
  py::array_t<T> out = cols > 0 ? py::array_t<T>({n, cols}) : py::array_t<T>(n);
  T* p = out.mutable_data();
  for (py::ssize_t i = 0; i < n; ++i)
    fill(r.correspondences[i], p + i * std::max<py::ssize_t>(cols, 1));
  return out;
}

// Objects as plain dicts of numbers and arrays (they are few; dicts print and serialise easily).
py::dict ObjectToPython(const ObjectSummary& o) {
  py::list views;
  for (const ObjectView& v : o.views) {
    py::array_t<std::int32_t> outline({static_cast<py::ssize_t>(v.outline.size()), py::ssize_t{2}});
    auto w = outline.mutable_unchecked<2>();
    for (size_t i = 0; i < v.outline.size(); ++i) {
      w(i, 0) = v.outline[i].x;
      w(i, 1) = v.outline[i].y;
    }
    py::dict d;
    d["view"] = v.view;
    d["box"] = py::make_tuple(v.box.x, v.box.y, v.box.width, v.box.height);
    d["score"] = v.score;
    d["outline"] = outline;
    views.append(d);
  }
  py::dict d;
  d["label"] = o.label;
  d["score"] = o.score;
  d["centroid"] = PointsToNumpy({o.centroid}).attr("reshape")(3);
  d["num_points"] = o.num_points;
  d["points"] = PointsToNumpy(o.points);
  d["views"] = views;
  return d;
}

py::list ObjectsToPython(const std::vector<ObjectSummary>& objects) {
  py::list out;
  for (const ObjectSummary& o : objects) out.append(ObjectToPython(o));
  return out;
}

py::dict Counts(const RegistrationResult& r) {
  py::dict d;
  d["keypoints_source"] = r.num_keypoints_source;
  d["keypoints_target"] = r.num_keypoints_target;
  d["correspondences"] = r.num_correspondences;
  d["inliers"] = r.num_inliers;
  d["ransac_iterations"] = r.ransac_iterations;
  return d;
}

std::string Repr(const RegistrationResult& r) {
  std::ostringstream s;
  s << "<zeroreg.Result " << (r.valid ? "valid" : "FAILED") << " path=" << PathName(r.path)
    << " inliers=" << r.num_inliers << "/" << r.num_correspondences << " reason='" << r.reason
    << "'>";
  return s.str();
}

// Pipeline::Register with the scans converted first (they need the GIL), then run without it.
// Either scan may be a PreparedScan (Pipeline.prepare); a plain one is then prepared here.
RegistrationResult RegisterWith(const Pipeline& pipeline, const py::handle& source,
                                const py::handle& target, const py::object& prior_T,
                                double prior_max_rotation_deg, double prior_max_translation_m) {
  std::optional<MotionPrior> prior;
  if (!prior_T.is_none()) {
    prior = MotionPrior{RequireRigid(prior_T, "prior"), prior_max_rotation_deg,
                        prior_max_translation_m};
  }
  const bool source_prepared = py::isinstance<PreparedScan>(source);
  const bool target_prepared = py::isinstance<PreparedScan>(target);
  if (!source_prepared && !target_prepared) {
    const Scan s = ScanFromPython(source, "source");
    const Scan t = ScanFromPython(target, "target");
    py::gil_scoped_release release;
    return pipeline.Register(s, t, prior);
  }
  PreparedScan s, t;
  Scan raw_s, raw_t;
  if (source_prepared) {
    s = source.cast<PreparedScan>();
  } else {
    raw_s = ScanFromPython(source, "source");
  }
  if (target_prepared) {
    t = target.cast<PreparedScan>();
  } else {
    raw_t = ScanFromPython(target, "target");
  }
  py::gil_scoped_release release;
  if (!source_prepared) s = pipeline.Prepare(raw_s);
  if (!target_prepared) t = pipeline.Prepare(raw_t);
  return pipeline.Register(s, t, prior);
}

PreparedScan PrepareWith(const Pipeline& pipeline, const py::handle& scan, bool as_target) {
  const Scan s = ScanFromPython(scan, "scan");
  py::gil_scoped_release release;
  return pipeline.Prepare(s, as_target);
}

void BindResult(py::module_& m) {
  py::class_<RegistrationResult>(m, "Result",
                                 "Result of one registration (RegistrationResult in C++).")
      .def_property_readonly(
          "T_target_source",
          [](const RegistrationResult& r) { return MatrixToNumpy(r.T_target_source); },
          "4x4 float64 rigid transform mapping source-frame points into the target frame.")
      .def_readonly("valid", &RegistrationResult::valid,
                    "False when the registration failed (see reason); never a silent identity.")
      .def_readonly("outside_prior", &RegistrationResult::outside_prior,
                    "True when the check passed but the pose lies beyond the motion prior given "
                    "to register() (so valid is False).")
      .def_readonly("reason", &RegistrationResult::reason)
      .def_property_readonly(
          "refusal",
          [](const RegistrationResult& r) -> py::object {
            if (r.refusal.test == RefusalTest::kNone) return py::none();
            py::dict d;
            d["test"] = RefusalTestName(r.refusal.test);
            d["measured"] = r.refusal.measured;
            d["threshold"] = r.refusal.threshold;
            return d;
          },
          "None when valid; else a dict: test (e.g. 'few_inliers', 'low_overlap', "
          "'outside_prior'), measured, threshold (units: RefusalTest in zeroreg/types.hpp).")
      .def_readonly("ambiguous", &RegistrationResult::ambiguous,
                    "True when two poses farther apart than the check can tell fit the scans "
                    "about equally well (valid is then False; see alternatives).")
      .def_property_readonly(
          "alternatives",
          [](const RegistrationResult& r) {
            py::list out = FromJson(ResultToJson(r, false)["alternatives"]);
            for (size_t i = 0; i < r.alternatives.size(); ++i) {
              py::dict alternative = out[i];
              alternative["T_target_source"] = MatrixToNumpy(r.alternatives[i].T_target_source);
            }
            return out;
          },
          "The poses that fit an ambiguous pair, the reported one first (or that a motion prior "
          "ruled out): a list of dicts with name, T_target_source (4x4 array), score, "
          "overlap, violation, brightness_rank_correlation, inliers, apart_m, outside_prior.")
      .def_property_readonly(
          "path", [](const RegistrationResult& r) { return PathName(r.path); },
          "Which source produced the transform (str), e.g. 'object', 'image-fallback', "
          "'geometry clique', 'prior icp'; the JSON result's 'path'.")
      .def_property_readonly("counts", &Counts,
                             "keypoints_source/target, correspondences, inliers, "
                             "ransac_iterations.")
      .def_readonly("inlier_ratio", &RegistrationResult::inlier_ratio)
      .def_readonly("inlier_rmse", &RegistrationResult::inlier_rmse, "Metres, over the inliers.")
      .def_property_readonly(
          "source_points",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<double>(r, 3, [](const Correspondence& c, double* p) {
              for (int k = 0; k < 3; ++k) p[k] = c.source[k];
            });
          },
          "(N, 3) float64, correspondences in the source scan frame, metres.")
      .def_property_readonly(
          "target_points",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<double>(r, 3, [](const Correspondence& c, double* p) {
              for (int k = 0; k < 3; ++k) p[k] = c.target[k];
            });
          },
          "(N, 3) float64, correspondences in the target scan frame, metres.")
      .def_property_readonly(
          "source_pixels",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<float>(r, 2, [](const Correspondence& c, float* p) {
              p[0] = c.source_pixel.x();
              p[1] = c.source_pixel.y();
            });
          },
          "(N, 2) float32 (x, y) pixel in the source view the correspondence came from.")
      .def_property_readonly(
          "target_pixels",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<float>(r, 2, [](const Correspondence& c, float* p) {
              p[0] = c.target_pixel.x();
              p[1] = c.target_pixel.y();
            });
          },
          "(N, 2) float32 (x, y) pixel in the target view.")
      .def_property_readonly(
          "correspondence_views",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<std::int32_t>(
                r, 0, [](const Correspondence& c, std::int32_t* p) { p[0] = c.view; });
          },
          "(N,) int32, source view each correspondence came from.")
      .def_property_readonly(
          "correspondence_target_views",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<std::int32_t>(
                r, 0, [](const Correspondence& c, std::int32_t* p) { p[0] = c.target_view; });
          },
          "(N,) int32, target view each correspondence came from (differs from "
          "correspondence_views only where the whole-image fallback matched different views).")
      .def_property_readonly(
          "scores",
          [](const RegistrationResult& r) {
            return CorrespondenceColumn<float>(
                r, 0, [](const Correspondence& c, float* p) { p[0] = c.score; });
          },
          "(N,) float32 matcher confidence.")
      .def_property_readonly(
          "is_inlier",
          [](const RegistrationResult& r) {
            py::array_t<bool> out(static_cast<py::ssize_t>(r.correspondences.size()));
            bool* p = out.mutable_data();
            for (size_t i = 0; i < r.correspondences.size(); ++i) {
              p[i] = i < r.is_inlier.size() && r.is_inlier[i];
            }
            return out;
          },
          "(N,) bool, RANSAC inlier mask under T_target_source.")
      .def_property_readonly(
          "source_objects",
          [](const RegistrationResult& r) { return ObjectsToPython(r.source_objects); },
          "Objects found in the source scan (paper §3.2), each a dict: label, score, centroid "
          "((3,) float64, scan frame, metres), num_points, views (list of dicts: view, box "
          "(x, y, width, height) in pixels, score, outline ((K, 2) int32 pixels)). Empty when the "
          "object path did not run.")
      .def_property_readonly(
          "target_objects",
          [](const RegistrationResult& r) { return ObjectsToPython(r.target_objects); },
          "Objects found in the target scan, as source_objects.")
      .def_property_readonly(
          "object_matches",
          [](const RegistrationResult& r) {
            py::list out;
            for (const ObjectMatchSummary& match : r.object_matches) {
              py::dict d;
              d["source"] = match.source;
              d["target"] = match.target;
              d["node_similarity"] = match.node_similarity;
              d["num_correspondences"] = match.num_correspondences;
              d["point_support"] = match.point_support;
              out.append(d);
            }
            return out;
          },
          "Matched object pairs (paper §3.3, Eq. 2), each a dict: source and target (indices into "
          "source_objects / target_objects), node_similarity (C = 1 + cosine of the semantic "
          "features), num_correspondences (point correspondences found inside the pair), "
          "point_support (the most of the point matches between the two objects that one rigid "
          "motion explains; -1 when object_match.min_point_support is 0 and "
          "object_match.motion_agreement is false).")
      .def_readonly("rejected_object_matches", &RegistrationResult::rejected_object_matches,
                    "Matches of Eq. 2 that the motion agreement (object_match.motion_agreement) "
                    "or the check against "
                    "the valid result (object_match.agree_with_result) dropped; they are not in "
                    "object_matches.")
      .def_property_readonly(
          "timings",
          [](const RegistrationResult& r) {
            py::dict d;  // insertion order = pipeline order, "total" last
            for (const StageTime& t : r.timings) d[py::str(t.stage)] = t.ms;
            return d;
          },
          "Wall time per stage in milliseconds, in pipeline order, 'total' last.")
      .def(
          "to_dict",
          [](const RegistrationResult& r, bool correspondences) {
            return FromJson(ResultToJson(r, correspondences));
          },
          py::arg("correspondences") = false,
          "The result as the CLI writes it under \"result\" (zeroreg::ResultToJson): every field "
          "of the C++ result, including any added later.")
      .def("__repr__", &Repr);
}

}  // namespace
}  // namespace zeroreg::python

PYBIND11_MODULE(_zeroreg, m) {
  using namespace zeroreg;          // NOLINT: the module body names many zeroreg types
  using namespace zeroreg::python;  // NOLINT
  m.doc() = "Compiled core of zeroreg; use the package `zeroreg` (docs/PYTHON.md).";
  m.attr("__version__") = ZEROREG_VERSION;

  // Bad input from C++ (files, configs, scans) is a ValueError in Python, like bad arrays.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      // Messages name files, whose names need not be UTF-8.
      const std::string text = e.what();
      PyObject* message = PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()),
                                               "backslashreplace");
      PyErr_SetObject(PyExc_ValueError, message);
      Py_XDECREF(message);
    }
  });

  BindResult(m);

  py::class_<PreparedScan>(
      m, "PreparedScan",
      "A scan as a Pipeline perceived it (Pipeline.prepare): features, detections, masks, "
      "objects and the clouds of verification and ICP, reused by every register() it is "
      "given to. Immutable; usable only with the Pipeline that made it.")
      .def_property_readonly("name", [](const PreparedScan& p) { return p.scan().name; })
      .def_property_readonly("num_views",
                             [](const PreparedScan& p) { return p.scan().views.size(); })
      .def_property_readonly("memory_bytes", &PreparedScan::MemoryBytes,
                             "approximate memory it holds (images, features, masks, clouds)")
      .def_property_readonly(
          "timings",
          [](const PreparedScan& p) {
            py::dict d;
            for (const StageTime& t : p.timings()) d[py::str(t.stage)] = t.ms;
            return d;
          },
          "wall time of preparing it per stage, milliseconds")
      .def("__repr__", [](const PreparedScan& p) {
        return "<zeroreg.PreparedScan '" + p.scan().name + "' " +
               std::to_string(p.scan().views.size()) + " view(s)>";
      });

  py::class_<Pipeline>(m, "Pipeline")
      .def(py::init([](const py::object& config, const py::object& seed) {
             return std::make_unique<Pipeline>(ConfigFromPython(config, seed));
           }),
           py::arg("config") = py::none(), py::arg("seed") = py::none())
      .def("register", &RegisterWith, py::arg("source"), py::arg("target"),
           py::arg("prior") = py::none(), py::arg("prior_max_rotation_deg") = 15.0,
           py::arg("prior_max_translation_m") = 0.30,
           "Registers source into target; either may be a PreparedScan from prepare() (the "
           "result is the same, bit for bit, as for the scans themselves). prior: a 4x4 motion "
           "prior T_target_source (odometry); only a pose within prior_max_rotation_deg and "
           "prior_max_translation_m of it can be valid, and ICP from it is tried when no source "
           "gives one (MotionPrior in C++).")
      .def("prepare", &PrepareWith, py::arg("scan"), py::arg("as_target") = true,
           "Everything that depends on one scan alone, done once: pass the PreparedScan to "
           "register() as often as needed. as_target=False for a scan that will only be a "
           "source: ICP's target geometry is then made the first time it is a target, if ever "
           "(same results).")
      .def_property_readonly("config",
                             [](const Pipeline& p) { return FromJson(ConfigToJson(p.config())); });

  m.def(
      "load_scan",
      [](const py::object& spec, double depth_scale) {
        DatasetOptions options;
        options.depth_scale = depth_scale;
        return ScanToPython(LoadScan(PathFromPython(spec, "spec"), options));
      },
      py::arg("spec"), py::arg("depth_scale") = 0.0);

  m.def(
      "read_color",
      [](const py::object& path) {
        return ColorToNumpy(ReadColorImage(PathFromPython(path, "path")));
      },
      py::arg("path"));

  m.def(
      "read_depth",
      [](const py::object& path_obj) {
        const std::string path = PathFromPython(path_obj, "path");
        const cv::Mat raw =
            detail::ReadImageFile(path, "depth image", detail::ImageMode::kUnchanged);
        if (raw.empty()) {
          throw MakeInputError(path, "cannot be read or decoded; expected a 16-bit PNG");
        }
        if (raw.type() != CV_16UC1) {
          throw MakeInputError(path, "not a 16-bit single-channel image; expected a 16-bit PNG");
        }
        py::array_t<std::uint16_t> out({raw.rows, raw.cols});
        cv::Mat view(raw.rows, raw.cols, CV_16UC1, out.mutable_data());
        raw.copyTo(view);
        return out;
      },
      py::arg("path"));

  // The CLI's error measures (rotation with the ground truth orthonormalised first, because
  // dataset rotations are not exactly orthonormal).
  m.def(
      "rotation_error_deg",
      [](const py::object& T, const py::object& T_gt) {
        return RotationErrorDeg(RequireRigid(T, "T"), RequireRigid(T_gt, "T_gt"));
      },
      py::arg("T"), py::arg("T_gt"));
  m.def(
      "translation_error_m",
      [](const py::object& T, const py::object& T_gt) {
        return TranslationErrorM(RequireRigid(T, "T"), RequireRigid(T_gt, "T_gt"));
      },
      py::arg("T"), py::arg("T_gt"));

  // How noisy a scan's depth is (src/estimate/depth_noise.hpp, docs/CONFIG.md "Depth noise"): the
  // a of sigma(d) = a d^2 that depth.noise_at_1m_m assumes, measured.
  m.def(
      "depth_noise_at_1m_m",
      [](const py::handle& scan) -> py::object {
        const Scan s = ScanFromPython(scan, "scan");
        std::optional<double> a;
        {
          py::gil_scoped_release release;
          a = MeasureDepthNoiseAt1m(s);
        }
        return a ? py::object(py::float_(*a)) : py::object(py::none());
      },
      py::arg("scan"),
      "The depth noise a of sigma(d) = a d^2 (metres at 1 m), measured from the scan's depth "
      "images (median over its views), or None when it has no measurable depth image.");

  // The geometric check of the verdict for any transform (docs/CONFIG.md "verify"): lets a user
  // check a transform from elsewhere, and the calibration script measure the check's separation.
  m.def(
      "verify",
      [](const py::handle& source, const py::handle& target, const py::object& T,
         const py::object& config) {
        const Scan s = ScanFromPython(source, "source");
        const Scan t = ScanFromPython(target, "target");
        const Transform T_target_source = RequireRigid(T, "T_target_source");
        const PipelineConfig c = ConfigFromPython(config, py::none());
        VerificationResult v;
        {
          py::gil_scoped_release release;
          v = VerifyRegistration(s, t, T_target_source, c.verify, c.depth);
        }
        RegistrationResult r;
        r.verification = v;
        return FromJson(ResultToJson(r, false)["verification"]);
      },
      py::arg("source"), py::arg("target"), py::arg("T_target_source"),
      py::arg("config") = py::none(),
      "Geometric check of T_target_source: each scan's depth rendered into the other's views. "
      "Returns a dict (passed, reason, overlap, violation, residual_rms_m, score, "
      "probe_contradicted, degenerate, ...).");

  // The pipeline's ICP refinement (config "refine") from any initial transform, e.g. odometry or a
  // transform from elsewhere, without correspondences to anchor it (src/estimate/icp.hpp).
  m.def(
      "refine",
      [](const py::handle& source, const py::handle& target, const py::object& T,
         const py::object& config) {
        const Scan s = ScanFromPython(source, "source");
        const Scan t = ScanFromPython(target, "target");
        const Transform initial = RequireRigid(T, "T_target_source");
        const PipelineConfig c = ConfigFromPython(config, py::none());
        IcpResult icp;
        {
          py::gil_scoped_release release;
          // The same geometry as the pipeline's refinement step.
          const std::vector<IcpStage> stages = IcpSchedule(c.refine, c.depth);
          icp = RefinePointToPlane(
              ScanIcpGeometry(s, stages, /*as_target=*/false, c.refine.pixel_stride),
              ScanIcpGeometry(t, stages, /*as_target=*/true, c.refine.pixel_stride), initial,
              stages);
        }
        py::dict out;
        out["T_target_source"] = MatrixToNumpy(icp.T_target_source);
        out["fitness"] = icp.fitness;
        out["rmse_m"] = icp.rmse;
        out["iterations"] = icp.iterations;
        return out;
      },
      py::arg("source"), py::arg("target"), py::arg("T_target_source"),
      py::arg("config") = py::none(),
      "Coarse-to-fine point-to-plane ICP (config 'refine') from T_target_source. Returns a dict "
      "(T_target_source, fitness, rmse_m, iterations).");

  // Whole recordings (docs/RECORDINGS.md): poses are "auto", "gt", "none", a TUM file or a dict
  // {frame id: 4x4}; options are RecordingsConfig's fields (ApplyRecordingsOptions).
  const auto recording = [](const py::object& spec, const py::object& poses,
                            const std::string& where) {
    RecordingInput r = ParseRecordingSpec(PathFromPython(spec, where));
    if (py::isinstance<py::dict>(poses)) {
      for (const auto& item : py::reinterpret_borrow<py::dict>(poses)) {
        if (!py::isinstance<py::int_>(item.first)) {
          throw MakeInputError(where + "_poses", "expected int frame ids as keys");
        }
        const int id = item.first.cast<int>();
        r.T_frame_camera[id] =
            RequireRigid(item.second, where + "_poses[" + std::to_string(id) + "]");
      }
      return r;
    }
    const std::string text = PathFromPython(poses, where + "_poses");
    if (text == "auto" || text == "gt") {
      r.T_frame_camera = GroundTruthPoses(r);
      if (text == "gt" && r.T_frame_camera.empty()) {
        throw MakeInputError(where + "_poses", "gt: " + r.root + " has no poses");
      }
    } else if (text != "none") {
      r.T_frame_camera = ReadTumTrajectory(text);
    }
    return r;
  };
  const auto recordings_config = [](const py::object& out, const py::object& config,
                                    const py::object& seed, const py::object& options) {
    RecordingsConfig c;
    c.pipeline = ConfigFromPython(config, seed);
    if (!out.is_none()) c.out_dir = PathFromPython(out, "out");
    ApplyRecordingsOptions(ToJson(options, "options"), "options", &c);
    return c;
  };
  m.def(
      "merge",
      [=](const py::object& a, const py::object& b, const py::object& poses_a,
          const py::object& poses_b, const py::object& out, const py::object& config,
          const py::object& seed, const py::object& options) {
        const RecordingInput ra = recording(a, poses_a, "a"), rb = recording(b, poses_b, "b");
        const RecordingsConfig c = recordings_config(out, config, seed, options);
        RecordingsResult r;
        {
          py::gil_scoped_release release;
          r = MergeRecordings(ra, rb, c);
        }
        return FromJson(RecordingsResultToJson(r));
      },
      py::arg("a"), py::arg("b"), py::arg("poses_a"), py::arg("poses_b"), py::arg("out"),
      py::arg("config"), py::arg("seed"), py::arg("options"));
  m.def(
      "close_loops",
      [=](const py::object& sequence, const py::object& odometry, const py::object& out,
          const py::object& config, const py::object& seed, const py::object& options) {
        const RecordingInput r = recording(sequence, odometry, "sequence");
        const RecordingsConfig c = recordings_config(out, config, seed, options);
        RecordingsResult result;
        {
          py::gil_scoped_release release;
          result = CloseLoops(r, c);
        }
        return FromJson(RecordingsResultToJson(result));
      },
      py::arg("sequence"), py::arg("odometry"), py::arg("out"), py::arg("config"), py::arg("seed"),
      py::arg("options"));

  m.def("default_config", []() { return FromJson(ConfigToJson(PipelineConfig())); });
  m.def("open3d_module_path", &open3d_module::LoadedModulePath,
        "The file of libzeroreg-open3d.so, what zeroreg takes from Open3D (FPFH, point cloud "
        "files, TSDF fusion), loading it if it is not yet (it is otherwise loaded only when "
        "needed); raises ValueError naming every place looked in when it cannot be loaded.");
}
