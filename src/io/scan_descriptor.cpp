// Generic scan descriptor (scan.json, docs/FORMATS.md): reading, writing and loading.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "io/image_checks.hpp"
#include "io/image_file.hpp"
#include "io/shown.hpp"
#include "io/text_parsing.hpp"
#include "open3d_module/open3d_module.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::set<std::string> kTopKeys = {"name", "views", "cloud", "T_world_scan_gt"};
const std::set<std::string> kViewKeys = {
    "color",       "depth",         "intrinsics",       "intrinsics_file",
    "depth_scale", "T_scan_camera", "T_world_camera_gt"};
const std::set<std::string> kIntrinsicsKeys = {"fx", "fy", "cx", "cy", "width", "height"};

// Rejects keys outside `allowed` so that a typo ("T_world_camera_GT") is not silently ignored.
void CheckKeys(const json& object, const std::set<std::string>& allowed, const std::string& path,
               const std::string& where) {
  for (const auto& item : object.items()) {
    if (allowed.count(item.key()) == 0) {
      std::string list;
      for (const auto& key : allowed) list += (list.empty() ? "" : ", ") + key;
      throw MakeInputError(path, where + "unknown key '" + detail::ShownText(item.key()) +
                                     "'; allowed keys: " + list);
    }
  }
}

std::string GetString(const json& object, const std::string& key, const std::string& path,
                      const std::string& where) {
  const json& v = object.at(key);
  if (!v.is_string()) throw MakeInputError(path, where + "'" + key + "' must be a string");
  return v.get<std::string>();
}

double GetNumber(const json& object, const std::string& key, const std::string& path,
                 const std::string& where) {
  const json& v = object.at(key);
  if (!v.is_number()) throw MakeInputError(path, where + "'" + key + "' must be a number");
  return v.get<double>();
}

// An image width or height: a whole number of pixels in [1, 65535] (the largest side JPEG and
// common PNG decoders accept). Checked before the cast to int, which would be undefined for 1e30.
int GetImageSide(const json& object, const std::string& key, const std::string& path,
                 const std::string& where) {
  const json& v = object.at(key);
  const double x = v.is_number() ? v.get<double>() : 0.0;
  if (!v.is_number() || !(x >= 1 && x <= 65535) || x != std::floor(x)) {
    throw MakeInputError(path, where + "'" + key + "' is " +
                                   detail::ShownText(detail::DumpJson(v)) +
                                   "; expected a whole number of pixels in [1, 65535]");
  }
  return static_cast<int>(x);
}

Transform GetTransform(const json& object, const std::string& key, const std::string& path,
                       const std::string& where) {
  const json& v = object.at(key);
  if (!v.is_array() || v.size() != 16) {
    throw MakeInputError(
        path, where + "'" + key + "' must be an array of 16 numbers (4x4 row-major transform)");
  }
  std::vector<double> numbers;
  for (const json& x : v) {
    if (!x.is_number()) throw MakeInputError(path, where + "'" + key + "' holds a non-number");
    numbers.push_back(x.get<double>());
  }
  return detail::RigidFromNumbers(numbers, path + ": " + where + "'" + key + "'");
}

json TransformToJson(const Transform& T) {
  json a = json::array();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a.push_back(T(r, c));
  }
  return a;
}

ScanDescriptorView ParseView(const json& v, const std::string& path, const std::string& dir,
                             const std::string& where) {
  if (!v.is_object()) throw MakeInputError(path, where + "must be an object");
  CheckKeys(v, kViewKeys, path, where);
  for (const char* required : {"color", "depth"}) {
    if (!v.contains(required)) {
      throw MakeInputError(path, where + "missing '" + required + "' (image path)");
    }
  }
  ScanDescriptorView view;
  view.color = GetString(v, "color", path, where);
  view.depth = GetString(v, "depth", path, where);
  const bool has_inline = v.contains("intrinsics");
  const bool has_file = v.contains("intrinsics_file");
  if (has_inline == has_file) {
    throw MakeInputError(path, where + "expected exactly one of 'intrinsics' or 'intrinsics_file'");
  }
  if (has_inline) {
    const json& k = v.at("intrinsics");
    const std::string kwhere = where + "intrinsics: ";
    if (!k.is_object()) throw MakeInputError(path, kwhere + "must be an object {fx, fy, cx, cy}");
    CheckKeys(k, kIntrinsicsKeys, path, kwhere);
    for (const char* required : {"fx", "fy", "cx", "cy"}) {
      if (!k.contains(required)) throw MakeInputError(path, kwhere + "missing '" + required + "'");
    }
    view.intrinsics.fx = GetNumber(k, "fx", path, kwhere);
    view.intrinsics.fy = GetNumber(k, "fy", path, kwhere);
    view.intrinsics.cx = GetNumber(k, "cx", path, kwhere);
    view.intrinsics.cy = GetNumber(k, "cy", path, kwhere);
    if (k.contains("width")) view.intrinsics.width = GetImageSide(k, "width", path, kwhere);
    if (k.contains("height")) view.intrinsics.height = GetImageSide(k, "height", path, kwhere);
    detail::CheckIntrinsics(view.intrinsics, path + ": " + kwhere);
  } else {
    const std::string file = detail::ResolvePath(dir, GetString(v, "intrinsics_file", path, where));
    view.intrinsics = ReadIntrinsicsFile(file, 0, 0);
  }
  if (v.contains("depth_scale")) {
    view.depth_scale = GetNumber(v, "depth_scale", path, where);
    detail::CheckDepthScale(view.depth_scale, path + ": " + where);
  }
  if (v.contains("T_scan_camera"))
    view.T_scan_camera = GetTransform(v, "T_scan_camera", path, where);
  if (v.contains("T_world_camera_gt")) {
    view.T_world_camera_gt = GetTransform(v, "T_world_camera_gt", path, where);
  }
  return view;
}

}  // namespace

void WriteScanDescriptor(const std::string& path, const ScanDescriptor& descriptor) {
  json j;
  j["name"] = descriptor.name;
  j["views"] = json::array();
  for (const ScanDescriptorView& v : descriptor.views) {
    json jv;
    jv["color"] = v.color;
    jv["depth"] = v.depth;
    json k = {{"fx", v.intrinsics.fx},
              {"fy", v.intrinsics.fy},
              {"cx", v.intrinsics.cx},
              {"cy", v.intrinsics.cy}};
    if (v.intrinsics.width > 0) k["width"] = v.intrinsics.width;
    if (v.intrinsics.height > 0) k["height"] = v.intrinsics.height;
    jv["intrinsics"] = k;
    jv["depth_scale"] = v.depth_scale;
    jv["T_scan_camera"] = TransformToJson(v.T_scan_camera);
    if (v.T_world_camera_gt) jv["T_world_camera_gt"] = TransformToJson(*v.T_world_camera_gt);
    j["views"].push_back(jv);
  }
  if (!descriptor.cloud.empty()) j["cloud"] = descriptor.cloud;
  if (descriptor.T_world_scan_gt)
    j["T_world_scan_gt"] = TransformToJson(*descriptor.T_world_scan_gt);
  // nlohmann writes doubles with max_digits10, so transforms round-trip exactly.
  detail::WriteFileAtomically(path, detail::DumpJson(j, 2) + "\n");
}

ScanDescriptor ReadScanDescriptor(const std::string& path) {
  const json j = detail::ReadJsonFile(path, "scan descriptor");
  if (!j.is_object()) throw MakeInputError(path, "scan descriptor must be a JSON object");
  CheckKeys(j, kTopKeys, path, "");
  const std::string dir = fs::path(path).parent_path().string();
  ScanDescriptor d;
  if (j.contains("name")) d.name = GetString(j, "name", path, "");
  if (d.name.empty()) d.name = fs::path(path).stem().string();
  if (!j.contains("views") || !j.at("views").is_array() || j.at("views").empty()) {
    throw MakeInputError(path, "'views' missing or empty; expected an array of at least one view");
  }
  const json& views = j.at("views");
  const size_t max_views = detail::MaxViewsPerScan();
  if (views.size() > max_views) {
    throw MakeInputError(path, "'views' lists " + std::to_string(views.size()) +
                                   " views, more than the limit of " + std::to_string(max_views) +
                                   " per scan (each costs ~10 MiB while registering; set "
                                   "ZEROREG_MAX_VIEWS to raise it)");
  }
  for (size_t k = 0; k < views.size(); ++k) {
    d.views.push_back(ParseView(views[k], path, dir, "views[" + std::to_string(k) + "]: "));
  }
  if (j.contains("cloud")) d.cloud = GetString(j, "cloud", path, "");
  if (j.contains("T_world_scan_gt"))
    d.T_world_scan_gt = GetTransform(j, "T_world_scan_gt", path, "");
  return d;
}

Scan LoadScanFromDescriptor(const std::string& path) {
  const ScanDescriptor d = ReadScanDescriptor(path);
  const std::string dir = fs::path(path).parent_path().string();
  Scan scan;
  scan.name = d.name;
  scan.T_world_scan_gt = d.T_world_scan_gt;
  for (size_t k = 0; k < d.views.size(); ++k) {
    const ScanDescriptorView& dv = d.views[k];
    const std::string where = path + ": views[" + std::to_string(k) + "]";
    View view = detail::LoadCheckedView(
        detail::ResolvePath(dir, dv.color), detail::ResolvePath(dir, dv.depth), dv.intrinsics,
        where + " intrinsics", dv.depth_scale, where + ".depth_scale");
    if ((dv.intrinsics.width > 0 && dv.intrinsics.width != view.intrinsics.width) ||
        (dv.intrinsics.height > 0 && dv.intrinsics.height != view.intrinsics.height)) {
      throw MakeInputError(path, "views[" + std::to_string(k) + "]: intrinsics are for " +
                                     std::to_string(dv.intrinsics.width) + "x" +
                                     std::to_string(dv.intrinsics.height) + " but the images are " +
                                     detail::SizeString(view.depth) + "; expected the same size");
    }
    view.name = d.name + "/" + std::to_string(k);
    view.T_scan_camera = dv.T_scan_camera;
    view.T_world_camera_gt = dv.T_world_camera_gt;
    scan.views.push_back(std::move(view));
  }
  // Either ground truth implies the other through T_scan_camera; fill in what is missing.
  if (!scan.T_world_scan_gt && scan.views[0].T_world_camera_gt) {
    scan.T_world_scan_gt = *scan.views[0].T_world_camera_gt * scan.views[0].T_scan_camera.inverse();
  }
  if (scan.T_world_scan_gt) {
    for (View& view : scan.views) {
      if (!view.T_world_camera_gt)
        view.T_world_camera_gt = *scan.T_world_scan_gt * view.T_scan_camera;
    }
  }
  if (!d.cloud.empty()) {
    const std::string cloud_path = detail::ResolvePath(dir, d.cloud);
    detail::RequireFile(cloud_path, "point cloud");
    std::vector<Eigen::Vector3d> points, colors;
    if (!open3d_module::Module().read_point_cloud(cloud_path, &points, &colors) || points.empty()) {
      throw MakeInputError(cloud_path,
                           "point cloud cannot be read or has no points; expected a .ply (or other "
                           "Open3D-readable) point cloud");
    }
    for (const auto& p : points) {
      if (!p.allFinite()) throw MakeInputError(cloud_path, "point cloud holds a non-finite point");
    }
    scan.points = std::move(points);
    if (!colors.empty() && colors.size() == scan.points.size()) scan.colors = std::move(colors);
  }
  return scan;
}

}  // namespace zeroreg
