// Dataset and file I/O. Everything that touches files lives here; the core works on the types of
// types.hpp. Every function throws InputError with a message naming the file, the problem and what
// was expected.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// ---- single files --------------------------------------------------------------------------

// 3x3 camera matrix as text (3DMatch `camera-intrinsics.txt`, ScanNet `intrinsic_color.txt` /
// 4x4 variants accepted: the top-left 3x3 is used). Width/height come from the images.
Intrinsics ReadIntrinsicsFile(const std::string& path, int width, int height);

// 4x4 row-major pose as text (3DMatch `frame-*.pose.txt`, ScanNet `pose/*.txt`); must be finite
// and rigid (orthonormal rotation within 1e-2, last row 0 0 0 1).
Transform ReadPoseFile(const std::string& path);

// Colour image (any format OpenCV reads) -> CV_8UC3 BGR.
cv::Mat ReadColorImage(const std::string& path);

// 16-bit depth PNG -> CV_32FC1 metres. raw / depth_scale = metres; raw 0 and 65535 are invalid
// (become 0). depth_scale: 1000 for 3DMatch / 7-Scenes / ScanNet (mm), 5000 for TUM.
cv::Mat ReadDepthImage(const std::string& path, double depth_scale);

// Loads one RGB-D view, checking that colour and depth have the same size and that depth has at
// least one valid pixel.
View LoadView(const std::string& color_path, const std::string& depth_path,
              const Intrinsics& intrinsics_without_size, double depth_scale);

// ---- datasets --------------------------------------------------------------------------------

enum class DatasetLayout {
  kThreeDMatch,  // frame-%06d.color.{jpg,png}, .depth.png, .pose.txt, camera-intrinsics.txt
  kTum,          // rgb.txt, depth.txt, groundtruth.txt (timestamp association), depth scale 5000
  kScanNet,      // color/N.jpg, depth/N.png, pose/N.txt, intrinsic/intrinsic_depth.txt
};

struct DatasetOptions {
  double depth_scale = 0.0;  // raw units per metre; 0 = the layout's default (1000, TUM 5000)
};

// A sequence of RGB-D frames on disk. Frame ids are the numbers in the file names (3DMatch,
// ScanNet) or the index in the associated rgb/depth list (TUM).
class Dataset {
 public:
  virtual ~Dataset() = default;
  virtual DatasetLayout layout() const = 0;
  virtual const std::string& root() const = 0;
  virtual std::vector<int> FrameIds() const = 0;  // sorted
  // Throws InputError if the id is unknown or a file is missing or malformed. T_world_camera_gt is
  // set when the layout has poses for the frame.
  virtual View LoadFrame(int frame_id) const = 0;
  // Raw depth units per metre the frames are read with.
  virtual double depth_scale() const = 0;
  // The files LoadFrame(frame_id) reads (colour, depth, pose when present, intrinsics), for cache
  // keys and for refusing an output that would overwrite one. Throws InputError for an unknown id.
  virtual std::vector<std::string> FrameFiles(int frame_id) const = 0;
};

// Detects the layout of `root` (a folder, or the 3DMatch `frames/` folder's parent) and opens it.
std::unique_ptr<Dataset> OpenDataset(const std::string& root, const DatasetOptions& options = {});

// A single frame as a scan: one view, identity T_scan_camera, empty point cloud,
// T_world_scan_gt = the frame's pose when known.
Scan ScanFromView(View view);

// Parses a scan specification given on the command line:
//   DIR@N          frame N of the dataset in DIR (any layout)
//   PATH.json      a scan descriptor (docs/FORMATS.md): explicit colour/depth/intrinsics/pose
//                  files per view plus an optional point cloud; `zeroreg fuse` writes one
//   DIR            DIR/scan.json
//   IMAGE          a 3DMatch-layout colour image frame-XXXXXX.color.{jpg,png}; depth, pose and
//                  camera-intrinsics.txt are found beside it (or in its parent folder)
Scan LoadScan(const std::string& spec, const DatasetOptions& options = {});

// The files LoadScan(spec) reads: the frame's files (DIR@N, IMAGE), or the descriptor and the
// views' images and cloud it names (PATH.json, DIR). Throws InputError as LoadScan does for a
// specification it cannot resolve.
std::vector<std::string> ScanInputFiles(const std::string& spec,
                                        const DatasetOptions& options = {});

// ---- scan descriptors (generic layout) -------------------------------------------------------

struct ScanDescriptorView {
  std::string color, depth;  // paths, relative to the descriptor's folder or absolute
  Intrinsics intrinsics;     // width/height taken from the images
  double depth_scale = 1000.0;
  Transform T_scan_camera = Transform::Identity();
  std::optional<Transform> T_world_camera_gt;
};
struct ScanDescriptor {
  std::string name;
  std::vector<ScanDescriptorView> views;
  std::string cloud;  // optional .ply path, scan frame
  std::optional<Transform> T_world_scan_gt;
};
void WriteScanDescriptor(const std::string& path, const ScanDescriptor& descriptor);
ScanDescriptor ReadScanDescriptor(const std::string& path);
Scan LoadScanFromDescriptor(const std::string& path);

// ---- 3DMatch logs ----------------------------------------------------------------------------

// One entry of gt.log / est.log: header "i j n" and T_i_j (maps fragment j into fragment i).
struct LogEntry {
  int i = 0, j = 0, n = 0;
  Transform T_i_j = Transform::Identity();
  int line = 0;  // line of the header in the file read (ReadLogFile), for messages
};
// One entry of gt.info: header "i j n" and the 6x6 information matrix.
struct InfoEntry {
  int i = 0, j = 0, n = 0;
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};
std::vector<LogEntry> ReadLogFile(const std::string& path);
std::vector<InfoEntry> ReadInfoFile(const std::string& path);
// Writes entries in the standard format (same layout as gt.log), so any 3DMatch scorer reads it.
void WriteLogFile(const std::string& path, const std::vector<LogEntry>& entries);

}  // namespace zeroreg
