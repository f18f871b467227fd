// Dataset layouts (3DMatch / 7-Scenes, TUM RGB-D, ScanNet export), layout detection, LoadScan.
// The formats are documented in docs/FORMATS.md.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <sstream>
#include <utility>

#include "io/image_checks.hpp"
#include "io/shown.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

namespace {

// The frame ids of an id -> file map, ascending.
std::vector<int> KeysOf(const std::map<int, std::string>& files) {
  std::vector<int> ids;
  for (const auto& [id, file] : files) ids.push_back(id);
  return ids;
}

namespace fs = std::filesystem;

constexpr double kThreeDMatchDepthScale = 1000.0;  // millimetres
constexpr double kScanNetDepthScale = 1000.0;      // millimetres
constexpr double kTumDepthScale = 5000.0;          // 1/5 mm (TUM file-format documentation)
// TUM's documented default intrinsics for the ROS OpenNI driver (used when no file is given).
constexpr double kTumDefaultF = 525.0, kTumDefaultCx = 319.5, kTumDefaultCy = 239.5;
// Maximum |dt| in seconds between an rgb timestamp and its depth / ground-truth timestamps
// (TUM's associate.py uses the same default).
constexpr double kTumMaxTimeDifference = 0.02;

// Folder path without a trailing separator, so that filename() gives the folder's name.
fs::path CleanFolder(const std::string& folder) {
  fs::path p = fs::path(folder).lexically_normal();
  if (p.filename().empty() && p.has_parent_path()) p = p.parent_path();
  return p;
}

// A short human-readable dataset name for view names: the folder's name, or its parent's name for
// a 3DMatch `frames/` folder.
std::string DatasetName(const fs::path& folder) {
  fs::path p = folder;
  if (p.filename() == "frames" && p.has_parent_path() && !p.parent_path().filename().empty()) {
    p = p.parent_path();
  }
  std::string name = p.filename().string();
  if (name.empty() || name == ".") name = fs::absolute(p).lexically_normal().filename().string();
  return name;
}

double ResolveDepthScale(const DatasetOptions& options, double layout_default) {
  if (options.depth_scale == 0.0) return layout_default;
  detail::CheckDepthScale(options.depth_scale, "--depth-scale (depth_scale)");
  return options.depth_scale;
}

[[noreturn]] void ThrowUnknownFrame(const std::string& root, int frame_id,
                                    const std::vector<int>& ids) {
  std::string range = ids.empty() ? "the dataset has no frames"
                                  : "known ids " + std::to_string(ids.front()) + ".." +
                                        std::to_string(ids.back()) + ", " +
                                        std::to_string(ids.size()) + " frames";
  throw MakeInputError(
      root, "frame id " + std::to_string(frame_id) + " not in the dataset (" + range + ")");
}

// Frame ids are at most 9 digits (they fit an int); files with longer numbers are ignored.
constexpr int kMaxFrameId = 999999999;

// Frame number from a digit string; -1 if it is above kMaxFrameId (leading zeros are fine).
int FrameIdFromDigits(const std::string& digits) {
  const size_t first = std::min(digits.find_first_not_of('0'), digits.size());
  const std::string significant = digits.substr(first);
  if (digits.empty() || significant.size() > 9) return -1;
  return significant.empty() ? 0 : std::stoi(significant);
}

bool IsDirectory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}
bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}
// For files a layout may or may not have (a frame's pose, TUM's ground truth): false when nothing
// is at `p`; an InputError when something other than a regular file is (a folder named
// frame-000000.pose.txt must not pass for "no ground truth").
bool OptionalFile(const fs::path& p, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(p, ec);
  if (ec || !fs::exists(status)) return false;
  if (IsFile(p)) return true;
  throw MakeInputError(p.string(), what + " is not a regular file (" +
                                       (fs::is_directory(status) ? "a folder" : "not a file") +
                                       "); expected a file, or nothing at this path");
}

// Where a layout's depth scale came from, for messages about its consequences.
std::string DepthScaleSource(const DatasetOptions& options, const char* layout) {
  return options.depth_scale == 0.0
             ? std::string("the ") + layout + " depth scale (set another with --depth-scale)"
             : std::string("--depth-scale");
}

// ---- 3DMatch / 7-Scenes -------------------------------------------------------------------------

const std::regex& ThreeDMatchColorRegex() {
  static const std::regex re(R"(frame-(\d+)\.color\.(jpg|png))");
  return re;
}

// True if `folder` holds at least one frame-XXXXXX.color.{jpg,png}.
bool HasThreeDMatchFrames(const fs::path& folder) {
  if (!IsDirectory(folder)) return false;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (std::regex_match(entry.path().filename().string(), ThreeDMatchColorRegex())) return true;
  }
  return false;
}

class ThreeDMatchDataset : public Dataset {
 public:
  ThreeDMatchDataset(const std::string& root, const fs::path& frames_dir, double depth_scale,
                     std::string scale_source)
      : root_(root),
        frames_dir_(frames_dir),
        depth_scale_(depth_scale),
        scale_source_(std::move(scale_source)),
        name_(DatasetName(frames_dir)) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(frames_dir_, ec)) {
      const std::string file = entry.path().filename().string();
      std::smatch m;
      if (!std::regex_match(file, m, ThreeDMatchColorRegex())) continue;
      const int id = FrameIdFromDigits(m[1].str());
      if (id < 0) continue;
      auto it = colors_.find(id);
      // Deterministic choice if both .jpg and .png exist: the lexicographically first name.
      if (it == colors_.end() || file < it->second) colors_[id] = file;
    }
    if (colors_.empty()) {
      throw MakeInputError(
          frames_dir_.string(),
          "no frame-XXXXXX.color.{jpg,png} files; expected a 3DMatch frame folder");
    }
    // camera-intrinsics.txt sits beside the frames or one level up (tsdf-fusion / 7-Scenes copies).
    const fs::path here = frames_dir_ / "camera-intrinsics.txt";
    const fs::path parent = frames_dir_.parent_path() / "camera-intrinsics.txt";
    if (IsFile(here)) {
      intrinsics_path_ = here.string();
    } else if (!frames_dir_.parent_path().empty() && IsFile(parent)) {
      intrinsics_path_ = parent.string();
    } else {
      throw MakeInputError(here.string(), "camera-intrinsics.txt not found (looked in " +
                                              frames_dir_.string() +
                                              " and its parent); expected a 3x3 camera matrix");
    }
    intrinsics_ = ReadIntrinsicsFile(intrinsics_path_, 0, 0);
  }

  DatasetLayout layout() const override { return DatasetLayout::kThreeDMatch; }
  const std::string& root() const override { return root_; }
  std::vector<int> FrameIds() const override { return KeysOf(colors_); }

  View LoadFrame(int frame_id) const override {
    auto it = colors_.find(frame_id);
    if (it == colors_.end()) {
      // Frames are listed by their colour images: say so when only the colour is missing.
      char stem[32];
      std::snprintf(stem, sizeof(stem), "frame-%06d", frame_id);
      if (IsFile(frames_dir_ / (std::string(stem) + ".depth.png"))) {
        throw MakeInputError((frames_dir_ / (std::string(stem) + ".color.jpg")).string(),
                             "colour image not found (neither .color.jpg nor .color.png), though "
                             "the frame's depth image " +
                                 std::string(stem) + ".depth.png exists");
      }
      ThrowUnknownFrame(root_, frame_id, FrameIds());
    }
    // Keep the file's own digit string (usually %06d) for the sibling files.
    const std::string stem = it->second.substr(0, it->second.find(".color."));
    const std::string color_path = (frames_dir_ / it->second).string();
    const std::string depth_path = (frames_dir_ / (stem + ".depth.png")).string();
    const fs::path pose_path = frames_dir_ / (stem + ".pose.txt");
    View view = detail::LoadCheckedView(color_path, depth_path, intrinsics_, intrinsics_path_,
                                        depth_scale_, scale_source_);
    view.name = name_ + "@" + std::to_string(frame_id);
    if (OptionalFile(pose_path, "pose file")) {
      view.T_world_camera_gt = ReadPoseFile(pose_path.string());
    }
    return view;
  }
  double depth_scale() const override { return depth_scale_; }
  std::vector<std::string> FrameFiles(int frame_id) const override {
    const auto it = colors_.find(frame_id);
    if (it == colors_.end()) ThrowUnknownFrame(root_, frame_id, FrameIds());
    const std::string stem = it->second.substr(0, it->second.find(".color."));
    return {(frames_dir_ / it->second).string(), (frames_dir_ / (stem + ".depth.png")).string(),
            (frames_dir_ / (stem + ".pose.txt")).string(), intrinsics_path_};
  }

 private:
  std::string root_;
  fs::path frames_dir_;
  double depth_scale_;
  std::string scale_source_;
  std::string name_;
  std::string intrinsics_path_;
  Intrinsics intrinsics_;
  std::map<int, std::string> colors_;  // id -> colour file name
};

// ---- TUM RGB-D ----------------------------------------------------------------------------------

struct TimedPath {
  double t = 0.0;
  std::string path;
};
struct TimedPose {
  double t = 0.0;
  Transform T;
};

std::string Trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

// Calls `fn(tokens, line_number)` for every non-empty, non-comment line.
template <typename Fn>
void ForEachDataLine(const std::string& path, const std::string& what, Fn fn) {
  detail::RequireFile(path, what);
  std::ifstream in(path);
  if (!in) throw MakeInputError(path, what + " cannot be opened for reading");
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1) line = detail::WithoutByteOrderMark(line);
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    std::istringstream ss(trimmed);
    std::vector<std::string> tokens;
    std::string token;
    while (ss >> token) tokens.push_back(token);
    fn(tokens, line_number);
  }
}

std::string LineWhere(const std::string& path, int line_number) {
  return path + ": line " + std::to_string(line_number);
}

std::vector<TimedPath> ReadTumList(const std::string& path, const std::string& what) {
  std::vector<TimedPath> list;
  ForEachDataLine(path, what, [&](const std::vector<std::string>& tokens, int line_number) {
    TimedPath item;
    if (tokens.size() != 2 || !detail::ParseDouble(tokens[0], &item.t) || !std::isfinite(item.t)) {
      throw InputError(LineWhere(path, line_number) +
                       ": malformed line; expected 'timestamp path' (comments start with #)");
    }
    item.path = tokens[1];
    list.push_back(item);
  });
  std::sort(list.begin(), list.end(),
            [](const TimedPath& a, const TimedPath& b) { return a.t < b.t; });
  return list;
}

std::vector<TimedPose> ReadTumGroundTruth(const std::string& path) {
  std::vector<TimedPose> poses;
  ForEachDataLine(
      path, "ground-truth file", [&](const std::vector<std::string>& tokens, int line_number) {
        double v[8];
        bool ok = tokens.size() == 8;
        for (size_t k = 0; ok && k < 8; ++k)
          ok = detail::ParseDouble(tokens[k], &v[k]) && std::isfinite(v[k]);
        if (!ok) {
          throw InputError(
              LineWhere(path, line_number) +
              ": malformed line; expected 8 finite numbers 'timestamp tx ty tz qx qy qz qw'");
        }
        const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen order: w, x, y, z
        if (std::abs(q.norm() - 1.0) > 0.1) {
          throw InputError(LineWhere(path, line_number) + ": quaternion norm " +
                           std::to_string(q.norm()) + " is far from 1; expected a unit quaternion");
        }
        TimedPose pose;
        pose.t = v[0];
        pose.T = Transform::Identity();
        pose.T.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
        pose.T.topRightCorner<3, 1>() = Eigen::Vector3d(v[1], v[2], v[3]);
        poses.push_back(pose);
      });
  std::sort(poses.begin(), poses.end(),
            [](const TimedPose& a, const TimedPose& b) { return a.t < b.t; });
  return poses;
}

// Index of the element of `sorted` (by .t) nearest to t, if within max_dt; -1 otherwise.
template <typename T>
int NearestWithin(const std::vector<T>& sorted, double t, double max_dt) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), t,
                             [](const T& item, double value) { return item.t < value; });
  int best = -1;
  double best_dt = max_dt;
  for (auto candidate : {it, it == sorted.begin() ? sorted.end() : std::prev(it)}) {
    if (candidate == sorted.end()) continue;
    const double dt = std::abs(candidate->t - t);
    if (dt <= best_dt) {
      best_dt = dt;
      best = static_cast<int>(candidate - sorted.begin());
    }
  }
  return best;
}

class TumDataset : public Dataset {
 public:
  TumDataset(const std::string& root, const fs::path& dir, double depth_scale,
             std::string scale_source)
      : root_(root),
        dir_(dir),
        depth_scale_(depth_scale),
        scale_source_(std::move(scale_source)),
        name_(DatasetName(dir)) {
    const std::vector<TimedPath> rgb = ReadTumList((dir_ / "rgb.txt").string(), "rgb list");
    const std::vector<TimedPath> depth = ReadTumList((dir_ / "depth.txt").string(), "depth list");
    const fs::path gt_path = dir_ / "groundtruth.txt";
    const std::vector<TimedPose> gt = OptionalFile(gt_path, "ground-truth file")
                                          ? ReadTumGroundTruth(gt_path.string())
                                          : std::vector<TimedPose>{};
    // Each rgb image takes the depth image with the nearest timestamp (rgb without depth within
    // 0.02 s is dropped) and the nearest ground-truth pose within 0.02 s (none -> no ground truth).
    for (const TimedPath& c : rgb) {
      const int d = NearestWithin(depth, c.t, kTumMaxTimeDifference);
      if (d < 0) continue;
      Frame frame;
      frame.color = detail::ResolvePath(dir_.string(), c.path);
      frame.depth = detail::ResolvePath(dir_.string(), depth[static_cast<size_t>(d)].path);
      const int g = NearestWithin(gt, c.t, kTumMaxTimeDifference);
      if (g >= 0) frame.T_world_camera = gt[static_cast<size_t>(g)].T;
      frames_.push_back(frame);
    }
    // TUM ships no intrinsics file; accept one, else use the documented ROS default.
    intrinsics_.fx = intrinsics_.fy = kTumDefaultF;
    intrinsics_.cx = kTumDefaultCx;
    intrinsics_.cy = kTumDefaultCy;
    for (const char* name : {"camera-intrinsics.txt", "intrinsics.txt"}) {
      if (OptionalFile(dir_ / name, "intrinsics file")) {
        intrinsics_path_ = (dir_ / name).string();
        intrinsics_ = ReadIntrinsicsFile(intrinsics_path_, 0, 0);
        break;
      }
    }
  }

  DatasetLayout layout() const override { return DatasetLayout::kTum; }
  const std::string& root() const override { return root_; }
  std::vector<int> FrameIds() const override {
    std::vector<int> ids(frames_.size());
    for (size_t k = 0; k < ids.size(); ++k) ids[k] = static_cast<int>(k);
    return ids;
  }
  View LoadFrame(int frame_id) const override {
    if (frame_id < 0 || frame_id >= static_cast<int>(frames_.size())) {
      ThrowUnknownFrame(root_, frame_id, FrameIds());
    }
    const Frame& frame = frames_[static_cast<size_t>(frame_id)];
    View view = detail::LoadCheckedView(frame.color, frame.depth, intrinsics_, intrinsics_path_,
                                        depth_scale_, scale_source_);
    view.name = name_ + "@" + std::to_string(frame_id);
    view.T_world_camera_gt = frame.T_world_camera;
    return view;
  }
  double depth_scale() const override { return depth_scale_; }
  std::vector<std::string> FrameFiles(int frame_id) const override {
    if (frame_id < 0 || frame_id >= static_cast<int>(frames_.size())) {
      ThrowUnknownFrame(root_, frame_id, FrameIds());
    }
    const Frame& frame = frames_[static_cast<size_t>(frame_id)];
    std::vector<std::string> files = {frame.color, frame.depth};
    for (const char* name :
         {"rgb.txt", "depth.txt", "groundtruth.txt", "camera-intrinsics.txt", "intrinsics.txt"}) {
      files.push_back((dir_ / name).string());
    }
    return files;
  }

 private:
  struct Frame {
    std::string color, depth;
    std::optional<Transform> T_world_camera;
  };
  std::string root_;
  fs::path dir_;
  double depth_scale_;
  std::string scale_source_;
  std::string name_;
  std::string intrinsics_path_;  // empty: TUM's documented default
  Intrinsics intrinsics_;
  std::vector<Frame> frames_;
};

// ---- ScanNet (SensReader export) ----------------------------------------------------------------

bool AllDigits(const std::string& s) {
  return !s.empty() &&
         std::all_of(s.begin(), s.end(), [](unsigned char ch) { return std::isdigit(ch); });
}

class ScanNetDataset : public Dataset {
 public:
  ScanNetDataset(const std::string& root, const fs::path& dir, double depth_scale,
                 std::string scale_source)
      : root_(root),
        dir_(dir),
        depth_scale_(depth_scale),
        scale_source_(std::move(scale_source)),
        name_(DatasetName(dir)) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir_ / "color", ec)) {
      const fs::path p = entry.path();
      const std::string ext = p.extension().string();
      if (!AllDigits(p.stem().string()) || (ext != ".jpg" && ext != ".png")) continue;
      const int id = FrameIdFromDigits(p.stem().string());
      if (id < 0) continue;
      auto it = colors_.find(id);
      if (it == colors_.end() || p.filename().string() < it->second)
        colors_[id] = p.filename().string();
    }
    if (colors_.empty()) {
      throw MakeInputError((dir_ / "color").string(),
                           "no N.jpg colour images; expected a ScanNet SensReader export");
    }
    // Colour is resized to the depth image, so the depth camera's intrinsics apply to both.
    intrinsics_path_ = (dir_ / "intrinsic" / "intrinsic_depth.txt").string();
    intrinsics_ = ReadIntrinsicsFile(intrinsics_path_, 0, 0);
  }

  DatasetLayout layout() const override { return DatasetLayout::kScanNet; }
  const std::string& root() const override { return root_; }
  std::vector<int> FrameIds() const override { return KeysOf(colors_); }

  View LoadFrame(int frame_id) const override {
    auto it = colors_.find(frame_id);
    if (it == colors_.end()) ThrowUnknownFrame(root_, frame_id, FrameIds());
    const std::string stem = fs::path(it->second).stem().string();
    const std::string color_path = (dir_ / "color" / it->second).string();
    const std::string depth_path = (dir_ / "depth" / (stem + ".png")).string();
    const fs::path pose_path = dir_ / "pose" / (stem + ".txt");
    cv::Mat color = ReadColorImage(color_path);
    const cv::Mat depth = ReadDepthImage(depth_path, depth_scale_);
    detail::CheckDepthRange(depth, depth_path, scale_source_, depth_scale_);
    if (color.size() != depth.size()) {
      // ScanNet colour (1296x968) and depth (640x480) come from different sensors; the standard
      // practice is to resample colour onto the depth grid and use the depth intrinsics.
      cv::Mat resized;
      cv::resize(color, resized, depth.size(), 0, 0, cv::INTER_AREA);
      color = resized;
    }
    View view = detail::MakeCheckedView(name_ + "@" + std::to_string(frame_id), color, color_path,
                                        depth, depth_path, intrinsics_, intrinsics_path_);
    if (OptionalFile(pose_path, "pose file")) {
      const std::vector<double> n = detail::ReadNumbers(pose_path.string(), "pose file");
      // SensReader writes -inf for frames whose tracking was lost: no ground truth there.
      const bool has_inf = std::any_of(n.begin(), n.end(), [](double v) { return std::isinf(v); });
      if (!has_inf) view.T_world_camera_gt = detail::RigidFromNumbers(n, pose_path.string());
    }
    return view;
  }
  double depth_scale() const override { return depth_scale_; }
  std::vector<std::string> FrameFiles(int frame_id) const override {
    const auto it = colors_.find(frame_id);
    if (it == colors_.end()) ThrowUnknownFrame(root_, frame_id, FrameIds());
    const std::string stem = fs::path(it->second).stem().string();
    return {(dir_ / "color" / it->second).string(), (dir_ / "depth" / (stem + ".png")).string(),
            (dir_ / "pose" / (stem + ".txt")).string(),
            (dir_ / "intrinsic" / "intrinsic_depth.txt").string()};
  }

 private:
  std::string root_;
  fs::path dir_;
  double depth_scale_;
  std::string scale_source_;
  std::string name_;
  std::string intrinsics_path_;
  Intrinsics intrinsics_;
  std::map<int, std::string> colors_;  // id -> colour file name
};

// The 3DMatch folder a frame file `frame-N.color.*` lies in, opened with the options' depth scale.
ThreeDMatchDataset FolderOfFrameFile(const fs::path& frame_file, const DatasetOptions& options) {
  fs::path folder = frame_file.parent_path();
  if (folder.empty()) folder = ".";
  return ThreeDMatchDataset(folder.string(), folder,
                            ResolveDepthScale(options, kThreeDMatchDepthScale),
                            DepthScaleSource(options, "3DMatch"));
}

std::string ToLower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return s;
}

}  // namespace

std::unique_ptr<Dataset> OpenDataset(const std::string& root, const DatasetOptions& options) {
  const fs::path dir = CleanFolder(root);
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw MakeInputError(root, "dataset folder not found");
  if (!IsDirectory(dir)) throw MakeInputError(root, "is not a folder; expected a dataset folder");
  if (HasThreeDMatchFrames(dir)) {
    return std::make_unique<ThreeDMatchDataset>(root, dir,
                                                ResolveDepthScale(options, kThreeDMatchDepthScale),
                                                DepthScaleSource(options, "3DMatch"));
  }
  if (HasThreeDMatchFrames(dir / "frames")) {
    return std::make_unique<ThreeDMatchDataset>(root, dir / "frames",
                                                ResolveDepthScale(options, kThreeDMatchDepthScale),
                                                DepthScaleSource(options, "3DMatch"));
  }
  if (IsFile(dir / "rgb.txt") && IsFile(dir / "depth.txt")) {
    return std::make_unique<TumDataset>(root, dir, ResolveDepthScale(options, kTumDepthScale),
                                        DepthScaleSource(options, "TUM"));
  }
  if (IsDirectory(dir / "color") && IsDirectory(dir / "depth")) {
    return std::make_unique<ScanNetDataset>(root, dir,
                                            ResolveDepthScale(options, kScanNetDepthScale),
                                            DepthScaleSource(options, "ScanNet"));
  }
  throw MakeInputError(root,
                       "unrecognised dataset layout; expected 3DMatch (frame-XXXXXX.color.jpg here "
                       "or in frames/), TUM (rgb.txt + depth.txt) or ScanNet (color/ + depth/ + "
                       "intrinsic/); see docs/FORMATS.md");
}

Scan ScanFromView(View view) {
  Scan scan;
  scan.name = view.name;
  view.T_scan_camera = Transform::Identity();
  scan.T_world_scan_gt = view.T_world_camera_gt;
  scan.views.push_back(std::move(view));
  return scan;
}

Scan LoadScan(const std::string& spec, const DatasetOptions& options) {
  if (spec.empty())
    throw MakeInputError("scan specification", "empty; expected DIR@N, PATH.json, DIR or an image");
  std::error_code ec;
  const bool exists = fs::exists(spec, ec);
  // DIR@N (checked first unless the whole string is an existing path, since paths may hold '@').
  const auto at = spec.rfind('@');
  if (!exists && at != std::string::npos) {
    const std::string dir = spec.substr(0, at);
    const std::string number = spec.substr(at + 1);
    if (!AllDigits(number)) {
      throw MakeInputError(spec, "frame id '" + detail::ShownText(number) +
                                     "' is not a non-negative integer; expected DIR@N");
    }
    if (FrameIdFromDigits(number) < 0) {
      throw MakeInputError(spec, "frame id " + detail::ShownText(number) +
                                     " is out of range; expected DIR@N with N in [0, " +
                                     std::to_string(kMaxFrameId) + "]");
    }
    if (!IsDirectory(dir))
      throw MakeInputError(spec, "dataset folder '" + dir + "' not found; expected DIR@N");
    const auto dataset = OpenDataset(dir, options);
    return ScanFromView(dataset->LoadFrame(std::stoi(number)));
  }
  if (!exists) {
    throw MakeInputError(spec,
                         "not found; expected DIR@N, PATH.json, DIR with scan.json, or a "
                         "3DMatch frame-XXXXXX.color.{jpg,png}");
  }
  if (IsDirectory(spec)) {
    const fs::path descriptor = fs::path(spec) / "scan.json";
    if (IsFile(descriptor)) return LoadScanFromDescriptor(descriptor.string());
    throw MakeInputError(spec, "folder has no scan.json; to load a frame of a dataset use DIR@N");
  }
  const fs::path path(spec);
  if (ToLower(path.extension().string()) == ".json") return LoadScanFromDescriptor(spec);
  std::smatch m;
  const std::string file = path.filename().string();
  if (std::regex_match(file, m, ThreeDMatchColorRegex())) {
    const ThreeDMatchDataset dataset = FolderOfFrameFile(path, options);
    const int id = FrameIdFromDigits(m[1].str());
    if (id < 0) {
      throw MakeInputError(spec,
                           "frame number is out of range; expected frame-N.color.jpg with N "
                           "in [0, " +
                               std::to_string(kMaxFrameId) + "]");
    }
    return ScanFromView(dataset.LoadFrame(id));
  }
  throw MakeInputError(spec,
                       "unrecognised scan specification; expected DIR@N, PATH.json, DIR with "
                       "scan.json, or a 3DMatch frame-XXXXXX.color.{jpg,png}");
}

std::vector<std::string> ScanInputFiles(const std::string& spec, const DatasetOptions& options) {
  std::error_code ec;
  const bool exists = fs::exists(spec, ec);
  const auto at = spec.rfind('@');
  if (!exists && at != std::string::npos) {  // DIR@N, as LoadScan reads it
    const std::string number = spec.substr(at + 1);
    if (!AllDigits(number) || number.size() > 9) return {};
    return OpenDataset(spec.substr(0, at), options)->FrameFiles(std::stoi(number));
  }
  if (!exists) return {};
  fs::path descriptor;
  if (IsDirectory(spec)) {
    descriptor = fs::path(spec) / "scan.json";
  } else if (ToLower(fs::path(spec).extension().string()) == ".json") {
    descriptor = spec;
  }
  if (!descriptor.empty()) {
    std::vector<std::string> files = {descriptor.string()};
    if (!IsFile(descriptor)) return files;
    const ScanDescriptor d = ReadScanDescriptor(descriptor.string());
    const std::string base = descriptor.parent_path().string();
    for (const ScanDescriptorView& v : d.views) {
      files.push_back(detail::ResolvePath(base, v.color));
      files.push_back(detail::ResolvePath(base, v.depth));
    }
    if (!d.cloud.empty()) files.push_back(detail::ResolvePath(base, d.cloud));
    return files;
  }
  std::smatch m;
  const fs::path path(spec);
  const std::string file = path.filename().string();
  if (std::regex_match(file, m, ThreeDMatchColorRegex())) {
    const int id = FrameIdFromDigits(m[1].str());
    if (id >= 0) return FolderOfFrameFile(path, options).FrameFiles(id);
  }
  return {spec};
}

}  // namespace zeroreg
