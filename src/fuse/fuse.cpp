#include "fuse/fuse.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "io/image_codec.hpp"
#include "io/image_file.hpp"
#include "io/text_parsing.hpp"
#include "open3d_module/open3d_module.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace fs = std::filesystem;
namespace {

// An Open3D TSDF volume (in the Open3D module), freed however the fusion ends.
class TsdfVolume {
 public:
  TsdfVolume(double voxel_length_m, double sdf_trunc_m)
      : api_(open3d_module::Module()), volume_(api_.tsdf_create(voxel_length_m, sdf_trunc_m)) {}
  ~TsdfVolume() { api_.tsdf_destroy(volume_); }
  TsdfVolume(const TsdfVolume&) = delete;
  TsdfVolume& operator=(const TsdfVolume&) = delete;

  // `T_fragment_camera` places the camera in the volume's frame.
  void Integrate(const View& view, const Transform& T_fragment_camera, double max_depth_m) {
    if (view.depth.type() != CV_32FC1 || view.color.type() != CV_8UC3 ||
        view.depth.size() != view.color.size()) {
      throw MakeInputError(view.name,
                           "colour and depth differ in size or type; TSDF fusion needs "
                           "8-bit BGR colour and float depth of the same size");
    }
    cv::Mat rgb;
    cv::cvtColor(view.color, rgb, cv::COLOR_BGR2RGB);
    open3d_module::RgbdFrame frame;
    frame.width = rgb.cols;
    frame.height = rgb.rows;
    frame.rgb = rgb.ptr<std::uint8_t>(0);
    frame.rgb_step = rgb.step[0];
    frame.depth = view.depth.ptr<float>(0);
    frame.depth_step = view.depth.step[0];
    frame.fx = view.intrinsics.fx;
    frame.fy = view.intrinsics.fy;
    frame.cx = view.intrinsics.cx;
    frame.cy = view.intrinsics.cy;
    frame.T_camera_volume = T_fragment_camera.inverse().matrix();  // extrinsic: fragment->camera
    api_.tsdf_integrate(volume_, frame, max_depth_m);
  }

  void Extract(double output_voxel_m, std::vector<Eigen::Vector3d>* points,
               std::vector<Eigen::Vector3d>* colors, std::vector<Eigen::Vector3d>* normals) {
    api_.tsdf_extract(volume_, output_voxel_m, points, colors, normals);
  }

 private:
  const open3d_module::Api& api_;
  void* volume_;
};

// Everything a fragment is made from: the settings, the depth scale the frames are read with and,
// per input file, its size and modification time (a frame replaced or edited in place changes
// them), so that a cached fragment is reused only for the very same inputs.
nlohmann::json FuseKey(const Dataset& dataset, const std::vector<int>& frame_ids,
                       const FuseConfig& c) {
  nlohmann::json files = nlohmann::json::array();
  std::set<std::string> seen;
  for (const int id : frame_ids) {
    for (const std::string& file : dataset.FrameFiles(id)) {
      if (!seen.insert(file).second) continue;
      struct stat info {};
      if (::stat(file.c_str(), &info) != 0) {
        files.push_back(
            {{"file", fs::absolute(file).lexically_normal().string()}, {"absent", true}});
        continue;
      }
      files.push_back({{"file", fs::absolute(file).lexically_normal().string()},
                       {"size", static_cast<long long>(info.st_size)},
                       {"mtime_ns", static_cast<long long>(info.st_mtim.tv_sec) * 1000000000LL +
                                        info.st_mtim.tv_nsec}});
    }
  }
  return {{"dataset", fs::absolute(dataset.root()).lexically_normal().string()},
          {"frames", frame_ids},
          {"depth_scale", dataset.depth_scale()},
          {"voxel_length_m", c.voxel_length_m},
          {"sdf_trunc_m", c.sdf_trunc_m},
          {"max_depth_m", c.max_depth_m},
          {"output_voxel_m", c.output_voxel_m},
          {"num_views", c.num_views},
          {"files", files},
          {"format_version", 2}};
}

}  // namespace

double MinFuseVoxelLengthM() {
  return detail::LimitFromEnvironment("ZEROREG_MIN_FUSE_VOXEL_M", FuseConfig::kMinVoxelLengthM);
}

void CheckFuseConfig(const FuseConfig& c) {
  const double min_voxel = MinFuseVoxelLengthM();
  if (!(c.voxel_length_m >= min_voxel && c.voxel_length_m <= FuseConfig::kMaxVoxelLengthM)) {
    std::ostringstream s;
    s << "is " << c.voxel_length_m << "; expected a voxel size in [" << min_voxel << ", "
      << FuseConfig::kMaxVoxelLengthM << "] metres (smaller voxels need memory without bound; "
      << "set ZEROREG_MIN_FUSE_VOXEL_M to lower the limit)";
    throw MakeInputError("--voxel", s.str());
  }
  if (c.num_views < 1) {
    throw MakeInputError("--views", "is " + std::to_string(c.num_views) +
                                        "; expected at least 1 view kept with the fragment");
  }
  // A fragment with more views than a scan.json may hold could be written but never read back.
  const size_t max_views = detail::MaxViewsPerScan();
  if (static_cast<size_t>(c.num_views) > max_views) {
    throw MakeInputError("--views", "is " + std::to_string(c.num_views) + "; expected at most " +
                                        std::to_string(max_views) +
                                        ", the most views a scan.json is read with "
                                        "(ZEROREG_MAX_VIEWS raises it)");
  }
  if (!(c.sdf_trunc_m > 0) || !(c.max_depth_m > 0) || !(c.output_voxel_m >= 0) ||
      !std::isfinite(c.sdf_trunc_m + c.max_depth_m + c.output_voxel_m)) {
    throw MakeInputError("fuse settings",
                         "sdf_trunc_m and max_depth_m must be > 0 and "
                         "output_voxel_m >= 0 (metres)");
  }
}

std::vector<int> ChooseViewFrames(const std::vector<int>& frame_ids, int num_views) {
  const int n = static_cast<int>(frame_ids.size());
  if (n == 0 || num_views <= 0) return {};
  if (num_views >= n) return frame_ids;
  if (num_views == 1) return {frame_ids.front()};
  std::vector<int> chosen;
  for (int i = 0; i < num_views; ++i) {
    // Evenly spaced, rounded down: k = 3 over 50 frames gives 0, 24, 49.
    chosen.push_back(frame_ids[static_cast<size_t>(i) * (n - 1) / (num_views - 1)]);
  }
  return chosen;
}

bool FuseFragment(const Dataset& dataset, const std::vector<int>& frame_ids,
                  const FuseConfig& config, const std::string& out_dir,
                  const std::function<void(int, int)>& progress) {
  if (frame_ids.empty()) throw MakeInputError("--frames", "no frames to fuse");
  CheckFuseConfig(config);
  const nlohmann::json key = FuseKey(dataset, frame_ids, config);
  const fs::path dir(out_dir), key_path = dir / "fuse.json";
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw MakeInputError(out_dir,
                         "exists and is not a folder; expected a folder for the fragment "
                         "(scan.json, cloud.ply, views) or a new name");
  }
  if (fs::exists(key_path) && fs::exists(dir / "scan.json") && fs::exists(dir / "cloud.ply")) {
    std::ifstream in(key_path);
    nlohmann::json cached = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (cached == key) return false;
  }
  fs::create_directories(dir, ec);
  if (ec) throw MakeInputError(out_dir, "cannot create the fragment folder (" + ec.message() + ")");

  TsdfVolume volume(config.voxel_length_m, config.sdf_trunc_m);
  const std::vector<int> view_ids = ChooseViewFrames(frame_ids, config.num_views);
  Transform T_world_fragment = Transform::Identity();
  ScanDescriptor descriptor;
  descriptor.name = dir.filename().string();
  for (size_t k = 0; k < frame_ids.size(); ++k) {
    const View view = dataset.LoadFrame(frame_ids[k]);
    if (!view.T_world_camera_gt) {
      throw MakeInputError(view.name, "has no pose; TSDF fusion needs a pose for every frame");
    }
    if (k == 0) T_world_fragment = *view.T_world_camera_gt;
    const Transform T_fragment_camera = T_world_fragment.inverse() * *view.T_world_camera_gt;
    volume.Integrate(view, T_fragment_camera, config.max_depth_m);

    if (std::find(view_ids.begin(), view_ids.end(), frame_ids[k]) != view_ids.end()) {
      const std::string stem = "view-" + std::to_string(frame_ids[k]);
      cv::Mat depth_mm;
      view.depth.convertTo(depth_mm, CV_16U, 1000.0);
      for (const auto& [name, image] :
           {std::pair{stem + ".color.png", view.color}, std::pair{stem + ".depth.png", depth_mm}}) {
        if (!detail::WriteImageFile((dir / name).string(), image)) {
          throw MakeInputError((dir / name).string(), "cannot write the fragment's view image");
        }
      }
      ScanDescriptorView v;
      v.color = stem + ".color.png";
      v.depth = stem + ".depth.png";
      v.intrinsics = view.intrinsics;
      v.depth_scale = 1000.0;
      v.T_scan_camera = T_fragment_camera;
      v.T_world_camera_gt = view.T_world_camera_gt;
      descriptor.views.push_back(v);
    }
    if (progress) progress(static_cast<int>(k) + 1, static_cast<int>(frame_ids.size()));
  }
  std::vector<Eigen::Vector3d> points, colors, normals;
  volume.Extract(config.output_voxel_m, &points, &colors, &normals);
  if (points.empty()) {
    throw MakeInputError(dataset.root(), "TSDF fusion produced an empty cloud (no valid depth?)");
  }
  const fs::path cloud_path = dir / "cloud.ply";
  if (!open3d_module::Module().write_point_cloud(cloud_path.string(), points, colors, normals)) {
    throw MakeInputError(cloud_path.string(), "cannot write the fused point cloud");
  }
  descriptor.cloud = "cloud.ply";
  descriptor.T_world_scan_gt = T_world_fragment;
  WriteScanDescriptor((dir / "scan.json").string(), descriptor);
  detail::WriteFileAtomically(key_path.string(), detail::DumpJson(key, 2) + "\n");
  return true;
}

}  // namespace zeroreg
