#include "objects/scene_objects.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <unordered_map>

#include "estimate/lift.hpp"

namespace zeroreg {
namespace {

using VoxelKey = std::tuple<int, int, int>;

VoxelKey VoxelOf(const Eigen::Vector3d& p, double voxel_m) {
  return {static_cast<int>(std::floor(p.x() / voxel_m)),
          static_cast<int>(std::floor(p.y() / voxel_m)),
          static_cast<int>(std::floor(p.z() / voxel_m))};
}

std::set<VoxelKey> VoxelSet(const std::vector<Eigen::Vector3d>& points, double voxel_m) {
  std::set<VoxelKey> voxels;
  for (const Eigen::Vector3d& p : points) voxels.insert(VoxelOf(p, voxel_m));
  return voxels;
}

double Cosine(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() == 0 || a.size() != b.size()) return 0.0;
  const double norms = a.norm() * b.norm();
  return norms > 0 ? a.dot(b) / norms : 0.0;
}

bool CompatibleLabels(const ObjectObservation& a, const ObjectObservation& b,
                      const ObjectsConfig& config) {
  return a.detection.label == b.detection.label ||
         Cosine(a.semantic, b.semantic) >= config.compatible_label_cosine;
}

// Label semantics say "both are chairs"; appearance says whether it is the same chair. Without
// comparable descriptors there is no evidence against the merge.
bool SimilarAppearance(const ObjectObservation& a, const ObjectObservation& b,
                       const ObjectsConfig& config) {
  if (config.association_min_appearance <= 0.0 || !Comparable(a.appearance, b.appearance)) {
    return true;
  }
  return AppearanceSimilarity(a.appearance, b.appearance) >= config.association_min_appearance;
}

// One point per voxel (the first one met, in order), so that an object seen in three views does
// not weigh three times in its centroid.
std::vector<Eigen::Vector3d> ThinPoints(const std::vector<Eigen::Vector3d>& points,
                                        double voxel_m) {
  std::set<VoxelKey> seen;
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : points) {
    if (seen.insert(VoxelOf(p, voxel_m)).second) out.push_back(p);
  }
  return out;
}

// Union-find with the smaller index as the representative, so the grouping does not depend on
// the order of the unions.
int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<Eigen::Vector3d> LiftMask(const View& view, const cv::Mat& mask,
                                      const ObjectsConfig& objects, const ViewLift& lift) {
  std::vector<Eigen::Vector3d> points;
  const int stride = PixelGrid{objects.pixel_stride}.StrideFor(mask.cols);
  for (int y = stride / 2; y < mask.rows; y += stride) {
    const uchar* row = mask.ptr<uchar>(y);
    for (int x = stride / 2; x < mask.cols; x += stride) {
      if (row[x] == 0) continue;
      if (auto p = LiftPixel(view, Eigen::Vector2f(static_cast<float>(x), static_cast<float>(y)),
                             lift)) {
        points.push_back(*p);
      }
    }
  }
  return points;
}

double VoxelOverlap(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                    double voxel_m) {
  const std::set<VoxelKey> va = VoxelSet(a, voxel_m), vb = VoxelSet(b, voxel_m);
  if (va.empty() || vb.empty()) return 0.0;
  const std::set<VoxelKey>& small = va.size() <= vb.size() ? va : vb;
  const std::set<VoxelKey>& large = va.size() <= vb.size() ? vb : va;
  size_t shared = 0;
  for (const VoxelKey& k : small) shared += large.count(k);
  return static_cast<double>(shared) / small.size();
}

void AppearanceCosines(const std::vector<SceneObject>& source,
                       const std::vector<SceneObject>& target, Eigen::MatrixXd* cosine,
                       Eigen::MatrixXd* comparable) {
  const auto n = static_cast<Eigen::Index>(source.size());
  const auto m = static_cast<Eigen::Index>(target.size());
  *cosine = Eigen::MatrixXd::Zero(n, m);
  *comparable = Eigen::MatrixXd::Zero(n, m);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index k = 0; k < m; ++k) {
      if (!Comparable(source[j].appearance, target[k].appearance)) continue;
      (*cosine)(j, k) = AppearanceSimilarity(source[j].appearance, target[k].appearance);
      (*comparable)(j, k) = 1.0;
    }
  }
}

std::vector<SceneObject> AssociateObservations(const std::vector<ObjectObservation>& observations,
                                               int num_views, const ObjectsConfig& config) {
  const int n = static_cast<int>(observations.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<std::set<int>> views_of_root(n);
  for (int i = 0; i < n; ++i) views_of_root[i].insert(observations[i].view);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      // Two detections in the same view are different objects (NMS already merged duplicates).
      if (observations[i].view == observations[j].view) continue;
      if (!CompatibleLabels(observations[i], observations[j], config)) continue;
      if (!SimilarAppearance(observations[i], observations[j], config)) continue;
      if (VoxelOverlap(observations[i].points, observations[j].points, config.association_voxel_m) <
          config.association_min_overlap) {
        continue;
      }
      const int a = Find(parent, i), b = Find(parent, j);
      if (a == b) continue;
      // One object is seen at most once per view: never merge two groups that share a view
      // (e.g. two chairs in one view that a single wide box of another view overlaps).
      bool shared_view = false;
      for (int view : views_of_root[a]) shared_view = shared_view || views_of_root[b].count(view);
      if (shared_view) continue;
      const int root = std::min(a, b), child = std::max(a, b);
      parent[child] = root;
      views_of_root[root].insert(views_of_root[child].begin(), views_of_root[child].end());
    }
  }

  std::vector<SceneObject> objects;
  std::unordered_map<int, size_t> object_of_root;
  for (int i = 0; i < n; ++i) {
    const int root = Find(parent, i);
    auto [it, inserted] = object_of_root.emplace(root, objects.size());
    if (inserted) objects.emplace_back();
    objects[it->second].observations.push_back(i);
  }

  std::vector<SceneObject> kept;
  for (SceneObject& object : objects) {
    std::set<int> views;
    std::vector<Eigen::Vector3d> points;
    Eigen::VectorXd semantic;
    int with_semantic = 0;
    std::vector<const Appearance*> appearances;
    for (int i : object.observations) {
      const ObjectObservation& o = observations[i];
      appearances.push_back(&o.appearance);
      views.insert(o.view);
      points.insert(points.end(), o.points.begin(), o.points.end());
      if (o.semantic.size() > 0) {
        semantic = with_semantic == 0 ? o.semantic : Eigen::VectorXd(semantic + o.semantic);
        ++with_semantic;
      }
      if (o.detection.score > object.score) {
        object.score = o.detection.score;
        object.label = o.detection.label;
      }
    }
    // Paper §3.2: with several views, objects detected in a single view are ignored.
    if (num_views >= 2 && static_cast<int>(views.size()) < config.min_views) continue;
    object.views.assign(views.begin(), views.end());
    if (with_semantic > 0) semantic /= static_cast<double>(with_semantic);
    object.semantic = semantic;
    object.appearance = MeanAppearance(appearances);
    object.points = ThinPoints(points, config.point_voxel_m);
    if (object.points.empty()) continue;
    for (const Eigen::Vector3d& p : object.points) object.centroid += p;
    object.centroid /= static_cast<double>(object.points.size());
    kept.push_back(std::move(object));
  }
  return kept;
}

}  // namespace zeroreg
