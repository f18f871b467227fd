// zeroreg-resize-scene: a copy of a 3DMatch-layout scene (../shared/data/*) at another image size,
// for measuring how the pipeline behaves on sensors of other resolutions (scripts/
// bench-resolution.sh, BENCHMARKS.md "Other sensors' resolutions"). Not installed.
//
//   zeroreg-resize-scene SCENE_DIR OUT_DIR WIDTH HEIGHT
//
// Colour is resampled bilinearly when enlarged and by area averaging when shrunk; depth by nearest
// neighbour (averaging depth across an edge would invent surfaces in free space); the intrinsics
// are scaled about pixel centres (c' = (c + 0.5) s - 0.5, f' = f s). Poses and the scene's other
// top-level files are copied unchanged. An existing complete copy is left as it is.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kColour = ".color.jpg", kDepth = ".depth.png", kPose = ".pose.txt";

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::array<double, 9> ReadIntrinsics(const fs::path& path) {
  std::ifstream in(path);
  std::array<double, 9> k{};
  for (double& v : k) {
    if (!(in >> v)) throw std::runtime_error(path.string() + ": expected 9 numbers (a 3x3 matrix)");
  }
  return k;
}

void WriteIntrinsics(const fs::path& path, std::array<double, 9> k, double sx, double sy) {
  k[0] *= sx;
  k[2] = (k[2] + 0.5) * sx - 0.5;
  k[4] *= sy;
  k[5] = (k[5] + 0.5) * sy - 0.5;
  std::ofstream out(path);
  char line[256];
  for (int r = 0; r < 3; ++r) {
    std::snprintf(line, sizeof(line), "%.12f %.12f %.12f\n", k[3 * r], k[3 * r + 1], k[3 * r + 2]);
    out << line;
  }
  if (!out) throw std::runtime_error(path.string() + ": could not write");
}

cv::Mat Read(const fs::path& path, int flags) {
  cv::Mat image = cv::imread(path.string(), flags);
  if (image.empty()) throw std::runtime_error(path.string() + ": could not read the image");
  return image;
}

void Write(const fs::path& path, const cv::Mat& image, const std::vector<int>& params = {}) {
  if (!cv::imwrite(path.string(), image, params)) {
    throw std::runtime_error(path.string() + ": could not write the image");
  }
}

int Run(const fs::path& scene, const fs::path& out, int width, int height) {
  const fs::path frames = fs::is_directory(scene / "frames") ? scene / "frames" : scene;
  const fs::path intrinsics_path = fs::exists(frames / "camera-intrinsics.txt")
                                       ? frames / "camera-intrinsics.txt"
                                       : scene / "camera-intrinsics.txt";
  const std::array<double, 9> intrinsics = ReadIntrinsics(intrinsics_path);
  const fs::path out_frames = out / "frames";
  const fs::path done_marker = out / ".complete";
  if (fs::exists(done_marker)) return 0;
  fs::create_directories(out_frames);
  for (const fs::directory_entry& entry : fs::directory_iterator(scene)) {
    if (entry.is_regular_file() && entry.path().filename() != "camera-intrinsics.txt") {
      fs::copy_file(entry.path(), out / entry.path().filename(),
                    fs::copy_options::overwrite_existing);
    }
  }
  std::vector<fs::path> colour;
  for (const fs::directory_entry& entry : fs::directory_iterator(frames)) {
    if (EndsWith(entry.path().filename().string(), kColour)) colour.push_back(entry.path());
  }
  if (colour.empty()) throw std::runtime_error(frames.string() + ": no frame-*.color.jpg here");
  double sx = 0, sy = 0;
  for (const fs::path& colour_path : colour) {
    const std::string name = colour_path.filename().string();
    const std::string stem = name.substr(0, name.size() - kColour.size());
    const cv::Mat image = Read(colour_path, cv::IMREAD_COLOR);
    const cv::Mat depth = Read(frames / (stem + kDepth), cv::IMREAD_UNCHANGED);
    const bool shrink = width * height < image.cols * image.rows;
    cv::Mat colour_out, depth_out;
    cv::resize(image, colour_out, cv::Size(width, height), 0, 0,
               shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
    cv::resize(depth, depth_out, cv::Size(width, height), 0, 0, cv::INTER_NEAREST);
    Write(out_frames / (stem + kColour), colour_out, {cv::IMWRITE_JPEG_QUALITY, 95});
    Write(out_frames / (stem + kDepth), depth_out);
    fs::copy_file(frames / (stem + kPose), out_frames / (stem + kPose),
                  fs::copy_options::overwrite_existing);
    sx = static_cast<double>(width) / image.cols;
    sy = static_cast<double>(height) / image.rows;
  }
  WriteIntrinsics(out / "camera-intrinsics.txt", intrinsics, sx, sy);
  std::ofstream(done_marker) << colour.size() << " frames\n";
  std::cout << out.string() << ": " << colour.size() << " frames at " << width << "x" << height
            << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: zeroreg-resize-scene SCENE_DIR OUT_DIR WIDTH HEIGHT\n";
    return 2;
  }
  try {
    const int width = std::stoi(argv[3]), height = std::stoi(argv[4]);
    if (width < 16 || height < 16) throw std::runtime_error("WIDTH and HEIGHT must be >= 16 px");
    return Run(argv[1], argv[2], width, height);
  } catch (const std::exception& e) {
    std::cerr << "zeroreg-resize-scene: " << e.what() << "\n";
    return 1;
  }
}
