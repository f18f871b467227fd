// What a scan looks like from a camera it was not taken from: each view's depth grid becomes a
// triangle mesh (neighbouring pixels joined unless depth jumps between them), coloured by the
// view's image, and the meshes are rasterised into a virtual pinhole camera with a z-buffer.
// Nothing is invented: pixels no triangle covers stay holes (depth 0, black), and every covered
// pixel carries the scan-frame 3D point it shows, so a feature matched on a rendering is a 3D
// point of the scan.
#pragma once

#include <opencv2/core.hpp>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

struct RenderConfig {
  // Depth readings outside the model's range are not surface, and a mesh triangle is drawn only
  // where the depth of its three corners differs by at most depth.edge_relative of the nearest
  // one: larger jumps are occlusion edges, not surface, and bridging them would paint a wall
  // between a chair and the floor behind it.
  DepthModel depth;
  // An invalid pixel whose nearest valid readings on both sides, along the row or the column,
  // are at most this many pixels away and agree (depth.edge_relative) is filled by linear
  // interpolation before meshing. HoloLens depth has a regular pattern of one- or two-pixel line
  // holes over the whole image; left open, each becomes a black crack in the rendering whose
  // edges the feature extractor takes for corners. 0 = no filling. Larger holes stay holes.
  int fill_hole_px = 2;
  // Mesh vertices every `stride` pixels of the view (1 = every pixel).
  int stride = 1;
};

struct RenderedView {
  cv::Mat color;    // CV_8UC3 (BGR), black where nothing was drawn
  cv::Mat depth;    // CV_32FC1, metres along the virtual camera's z, 0 = hole
  cv::Mat points;   // CV_32FC3, the scan-frame point each pixel shows (valid where depth > 0)
  int covered = 0;  // pixels with depth > 0
};

// The depth of `view` with its thin holes filled (RenderConfig::fill_hole_px).
cv::Mat FillThinHoles(const cv::Mat& depth, const RenderConfig& config);

// Renders every view of `scan` into a camera with intrinsics K (its width and height give the
// image size) and pose T_scan_virtual (virtual camera -> scan frame; OpenCV axes: x right, y
// down, z forward). Pixel centres are at integer coordinates, as LiftPixel reads them.
RenderedView RenderScan(const Scan& scan, const Transform& T_scan_virtual, const Intrinsics& K,
                        const RenderConfig& config = RenderConfig());

}  // namespace zeroreg
