// zeroreg-resize-scene: a copy of a 3DMatch-layout scene (../shared/data/*) at another image size,
// for measuring how the pipeline behaves on sensors of other resolutions (scripts/
// bench-resolution.sh, BENCHMARKS.md "Capture conditions"). Not installed.
//
//   zeroreg-resize-scene SCENE_DIR OUT_DIR WIDTH HEIGHT [DEPTH_NOISE_AT_1M_M]
//
// Colour is resampled bilinearly when enlarged and by area averaging when shrunk; depth by nearest
// neighbour (averaging depth across an edge would invent surfaces in free space); the intrinsics
// are scaled about pixel centres (c' = (c + 0.5) s - 0.5, f' = f s). Poses and the scene's other
// top-level files are copied unchanged. An existing complete copy is left as it is.
//
// With DEPTH_NOISE_AT_1M_M > 0, Gaussian noise of sigma(d) = DEPTH_NOISE_AT_1M_M * d^2 (metres;
// the structured-light / stereo model of docs/CONFIG.md, i.e. constant noise in disparity) is
// added to every valid depth reading after resizing, independently per pixel and with a seed per
// frame (the same copy every time): a noisier sensor than the scene's own (a RealSense-class
// stereo camera is several times Kinect v1's 1.5 mm at 1 m). Depth must be in millimetres (the
// 3DMatch layout of ../shared/data).
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
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

// FNV-1a of a frame's name: its noise seed, the same on every platform.
std::uint32_t Seed(const std::string& name) {
  std::uint32_t h = 2166136261u;
  for (const char c : name) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
  return h;
}

// Adds sigma(d) = noise_at_1m * d^2 Gaussian noise to a CV_16U millimetre depth image. 0 and
// 65535 mark missing readings (7-Scenes uses both) and stay missing; a reading the noise pushes
// out of the 16-bit range becomes missing too, as a real sensor drops it.
void AddDepthNoise(cv::Mat& depth_mm, double noise_at_1m, std::uint32_t seed) {
  if (depth_mm.type() != CV_16UC1) throw std::runtime_error("depth noise needs 16-bit depth PNGs");
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (int y = 0; y < depth_mm.rows; ++y) {
    auto* row = depth_mm.ptr<std::uint16_t>(y);
    for (int x = 0; x < depth_mm.cols; ++x) {
      if (row[x] == 0 || row[x] == 65535) continue;
      const double d = row[x] / 1000.0;
      const long noisy_mm = std::lround(1000.0 * (d + noise_at_1m * d * d * unit(rng)));
      row[x] = noisy_mm >= 1 && noisy_mm < 65535 ? static_cast<std::uint16_t>(noisy_mm) : 0;
    }
  }
}

int Run(const fs::path& scene, const fs::path& out, int width, int height, double noise_at_1m) {
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
    const bool shrink =
        static_cast<long>(width) * height < static_cast<long>(image.cols) * image.rows;
    cv::Mat colour_out, depth_out;
    cv::resize(image, colour_out, cv::Size(width, height), 0, 0,
               shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
    cv::resize(depth, depth_out, cv::Size(width, height), 0, 0, cv::INTER_NEAREST);
    if (noise_at_1m > 0) {
      AddDepthNoise(depth_out, noise_at_1m, Seed(stem));
    }
    Write(out_frames / (stem + kColour), colour_out, {cv::IMWRITE_JPEG_QUALITY, 95});
    Write(out_frames / (stem + kDepth), depth_out);
    fs::copy_file(frames / (stem + kPose), out_frames / (stem + kPose),
                  fs::copy_options::overwrite_existing);
    sx = static_cast<double>(width) / image.cols;
    sy = static_cast<double>(height) / image.rows;
  }
  WriteIntrinsics(out / "camera-intrinsics.txt", intrinsics, sx, sy);
  std::ofstream marker(done_marker);
  marker << colour.size() << " frames\n";
  if (!marker) throw std::runtime_error(done_marker.string() + ": could not write");
  std::cout << out.string() << ": " << colour.size() << " frames at " << width << "x" << height
            << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::cerr
        << "usage: zeroreg-resize-scene SCENE_DIR OUT_DIR WIDTH HEIGHT [DEPTH_NOISE_AT_1M_M]\n";
    return 2;
  }
  try {
    const auto number = [](const char* text, const char* what) {
      std::size_t used = 0;
      double value = 0;
      try {
        value = std::stod(text, &used);
      } catch (const std::logic_error&) {  // invalid_argument, out_of_range
        used = 0;
      }
      if (used == 0 || used != std::string(text).size()) {
        throw std::runtime_error(std::string(what) + " '" + text + "' is not a number");
      }
      return value;
    };
    const double w = number(argv[3], "WIDTH"), h = number(argv[4], "HEIGHT");
    if (!(w >= 16 && h >= 16 && w <= 16384 && h <= 16384) || w != static_cast<int>(w) ||
        h != static_cast<int>(h)) {
      throw std::runtime_error("WIDTH and HEIGHT must be whole numbers of pixels in [16, 16384]");
    }
    const int width = static_cast<int>(w), height = static_cast<int>(h);
    const double noise = argc == 6 ? number(argv[5], "DEPTH_NOISE_AT_1M_M") : 0.0;
    if (!(noise >= 0 && noise < 1)) {
      throw std::runtime_error("DEPTH_NOISE_AT_1M_M must be in [0, 1) metres");
    }
    return Run(argv[1], argv[2], width, height, noise);
  } catch (const std::exception& e) {
    std::cerr << "zeroreg-resize-scene: " << e.what() << "\n";
    return 1;
  }
}
