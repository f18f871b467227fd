#include "synthesis/render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace zeroreg {
namespace {

bool InRange(float z, const RenderConfig& c) { return z >= c.depth.min_m && z <= c.depth.max_m; }

bool Agree(float a, float b, const RenderConfig& c) {
  return std::abs(a - b) <= c.depth.edge_relative * std::min(a, b);
}

// One mesh vertex seen from the virtual camera.
struct Vertex {
  bool valid = false;
  float x = 0, y = 0;    // virtual pixel
  float inv_z = 0;       // 1 / depth in the virtual camera
  float depth = 0;       // depth in the view it comes from (for the jump test)
  Eigen::Vector3f bgr;   // colour
  Eigen::Vector3f scan;  // scan-frame point
};

// Triangles whose screen box is larger than this on a side are skipped: a mesh cell a few pixels
// wide in its own view magnified that much lies almost edge-on to the virtual camera or grazes its
// image plane, and would smear one colour over much of the image.
constexpr float kMaxTriangleSpanPx = 256.0f;
// Vertices nearer to the virtual camera than this are not drawn (they would project to infinity).
constexpr float kNearPlaneM = 0.05f;

struct Target {
  RenderedView* out;
  cv::Mat zbuffer;  // CV_32FC1, depth of the nearest surface drawn so far
};

void DrawTriangle(const Vertex& a, const Vertex& b, const Vertex& c, Target* t) {
  const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (std::abs(area) < 1e-9f) return;
  const float min_x = std::min({a.x, b.x, c.x}), max_x = std::max({a.x, b.x, c.x});
  const float min_y = std::min({a.y, b.y, c.y}), max_y = std::max({a.y, b.y, c.y});
  if (max_x - min_x > kMaxTriangleSpanPx || max_y - min_y > kMaxTriangleSpanPx) return;
  const int width = t->zbuffer.cols, height = t->zbuffer.rows;
  // Vertices projected onto a pixel centre land a rounding error either side of it: the box and
  // the inside test allow kSlackPx, or whole rows on a triangle edge would be lost.
  constexpr float kSlackPx = 1e-3f;
  const int x0 = std::max(0, static_cast<int>(std::ceil(min_x - kSlackPx)));
  const int x1 = std::min(width - 1, static_cast<int>(std::floor(max_x + kSlackPx)));
  const int y0 = std::max(0, static_cast<int>(std::ceil(min_y - kSlackPx)));
  const int y1 = std::min(height - 1, static_cast<int>(std::floor(max_y + kSlackPx)));
  const float inv_area = 1.0f / area;
  for (int y = y0; y <= y1; ++y) {
    float* zrow = t->zbuffer.ptr<float>(y);
    for (int x = x0; x <= x1; ++x) {
      const float px = static_cast<float>(x), py = static_cast<float>(y);
      // Barycentric weights from the edge functions; a pixel on a shared edge is drawn by both
      // triangles, which the z-buffer makes harmless.
      const float l0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv_area;
      const float l1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv_area;
      const float l2 = 1.0f - l0 - l1;
      constexpr float kEdge = -1e-4f;
      if (l0 < kEdge || l1 < kEdge || l2 < kEdge) continue;
      // Perspective-correct interpolation: 1/z and attribute/z are linear on the screen.
      const float inv_z = l0 * a.inv_z + l1 * b.inv_z + l2 * c.inv_z;
      if (inv_z <= 0) continue;
      const float z = 1.0f / inv_z;
      if (z >= zrow[x]) continue;
      zrow[x] = z;
      const float w0 = l0 * a.inv_z * z, w1 = l1 * b.inv_z * z, w2 = l2 * c.inv_z * z;
      const Eigen::Vector3f bgr = w0 * a.bgr + w1 * b.bgr + w2 * c.bgr;
      const Eigen::Vector3f p = w0 * a.scan + w1 * b.scan + w2 * c.scan;
      cv::Vec3b& colour = t->out->color.at<cv::Vec3b>(y, x);
      for (int k = 0; k < 3; ++k) {
        colour[k] = static_cast<uchar>(std::clamp(std::lround(bgr[k]), 0L, 255L));
      }
      t->out->points.at<cv::Vec3f>(y, x) = cv::Vec3f(p.x(), p.y(), p.z());
    }
  }
}

void DrawView(const View& view, const Transform& T_virtual_scan, const Intrinsics& K,
              const RenderConfig& config, Target* t) {
  const cv::Mat depth = FillThinHoles(view.depth, config);
  const int stride = std::max(1, config.stride);
  const int cols = (depth.cols - 1) / stride + 1, rows = (depth.rows - 1) / stride + 1;
  const Intrinsics& Kv = view.intrinsics;
  const Eigen::Matrix4d T_virtual_camera = T_virtual_scan * view.T_scan_camera;
  const Eigen::Matrix3f R = T_virtual_camera.topLeftCorner<3, 3>().cast<float>();
  const Eigen::Vector3f tr = T_virtual_camera.topRightCorner<3, 1>().cast<float>();
  const Eigen::Matrix3f Rs = view.T_scan_camera.topLeftCorner<3, 3>().cast<float>();
  const Eigen::Vector3f ts = view.T_scan_camera.topRightCorner<3, 1>().cast<float>();
  std::vector<Vertex> grid(static_cast<size_t>(cols) * rows);
  for (int r = 0; r < rows; ++r) {
    const int v = r * stride;
    const float* drow = depth.ptr<float>(v);
    const cv::Vec3b* crow = view.color.ptr<cv::Vec3b>(v);
    for (int c = 0; c < cols; ++c) {
      const int u = c * stride;
      const float z = drow[u];
      if (!InRange(z, config)) continue;
      const Eigen::Vector3f camera(
          (static_cast<float>(u) - static_cast<float>(Kv.cx)) / static_cast<float>(Kv.fx) * z,
          (static_cast<float>(v) - static_cast<float>(Kv.cy)) / static_cast<float>(Kv.fy) * z, z);
      const Eigen::Vector3f seen = R * camera + tr;
      if (seen.z() < kNearPlaneM) continue;
      Vertex& out = grid[static_cast<size_t>(r) * cols + c];
      out.valid = true;
      out.inv_z = 1.0f / seen.z();
      out.x = static_cast<float>(K.fx) * seen.x() * out.inv_z + static_cast<float>(K.cx);
      out.y = static_cast<float>(K.fy) * seen.y() * out.inv_z + static_cast<float>(K.cy);
      out.depth = z;
      out.bgr = Eigen::Vector3f(crow[u][0], crow[u][1], crow[u][2]);
      out.scan = Rs * camera + ts;
    }
  }
  const auto joined = [&](const Vertex& a, const Vertex& b, const Vertex& c) {
    return a.valid && b.valid && c.valid && Agree(a.depth, b.depth, config) &&
           Agree(b.depth, c.depth, config) && Agree(a.depth, c.depth, config);
  };
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < cols; ++c) {
      const Vertex& v00 = grid[static_cast<size_t>(r) * cols + c];
      const Vertex& v01 = grid[static_cast<size_t>(r) * cols + c + 1];
      const Vertex& v10 = grid[static_cast<size_t>(r + 1) * cols + c];
      const Vertex& v11 = grid[static_cast<size_t>(r + 1) * cols + c + 1];
      if (joined(v00, v01, v10)) DrawTriangle(v00, v01, v10, t);
      if (joined(v01, v11, v10)) DrawTriangle(v01, v11, v10, t);
    }
  }
}

}  // namespace

cv::Mat FillThinHoles(const cv::Mat& depth, const RenderConfig& config) {
  const int r = config.fill_hole_px;
  if (r <= 0) return depth;
  cv::Mat out = depth.clone();
  const auto at = [&](int y, int x) { return depth.at<float>(y, x); };
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      if (InRange(at(y, x), config)) continue;
      // Nearest valid reading on each side along the row, then along the column.
      for (const auto& [dx, dy] : {std::pair<int, int>{1, 0}, std::pair<int, int>{0, 1}}) {
        int before = 0, after = 0;
        for (int k = 1; k <= r && before == 0; ++k) {
          const int yy = y - k * dy, xx = x - k * dx;
          if (yy < 0 || xx < 0) break;
          if (InRange(at(yy, xx), config)) before = k;
        }
        for (int k = 1; k <= r && after == 0; ++k) {
          const int yy = y + k * dy, xx = x + k * dx;
          if (yy >= depth.rows || xx >= depth.cols) break;
          if (InRange(at(yy, xx), config)) after = k;
        }
        if (before == 0 || after == 0 || before + after - 1 > r) continue;
        const float a = at(y - before * dy, x - before * dx);
        const float b = at(y + after * dy, x + after * dx);
        if (!Agree(a, b, config)) continue;
        const float w = static_cast<float>(before) / static_cast<float>(before + after);
        out.at<float>(y, x) = a + w * (b - a);
        break;
      }
    }
  }
  return out;
}

RenderedView RenderScan(const Scan& scan, const Transform& T_scan_virtual, const Intrinsics& K,
                        const RenderConfig& config) {
  RenderedView out;
  out.color = cv::Mat(K.height, K.width, CV_8UC3, cv::Scalar::all(0));
  out.depth = cv::Mat(K.height, K.width, CV_32FC1, cv::Scalar(0));
  out.points = cv::Mat(K.height, K.width, CV_32FC3, cv::Scalar::all(0));
  Target t{&out, cv::Mat(K.height, K.width, CV_32FC1,
                         cv::Scalar(std::numeric_limits<float>::infinity()))};
  const Transform T_virtual_scan = T_scan_virtual.inverse();
  for (const View& view : scan.views) {
    if (view.depth.empty() || view.color.size() != view.depth.size()) continue;
    DrawView(view, T_virtual_scan, K, config, &t);
  }
  for (int y = 0; y < K.height; ++y) {
    const float* z = t.zbuffer.ptr<float>(y);
    float* d = out.depth.ptr<float>(y);
    for (int x = 0; x < K.width; ++x) {
      if (std::isfinite(z[x])) {
        d[x] = z[x];
        ++out.covered;
      }
    }
  }
  return out;
}

}  // namespace zeroreg
