// Scene graphs over detected objects (paper §3.3, Eq. 1) and the node similarity matrix C.
//
// Pure Eigen: one row per object, centroids in metres, semantic vectors of any dimension d (CLIP
// text embeddings, or one-hot label vectors for the "without CLIP" ablation). See docs/MATCHING.md.
#pragma once

#include <Eigen/Core>

#include "zeroreg/config.hpp"

namespace zeroreg {

// Affinity matrix W of Eq. 1 (N x N, zero diagonal):
//   W_jk = 1 + cos(s_j, s_k)  if v_k in kNN(v_j) (k != j),  else 0,
// made symmetric with max when config.symmetric. Ties in distance go to the lower index, so the
// graph is deterministic. Throws InputError when the row counts differ, centroids are not N x 3,
// values are not finite or knn < 1.
Eigen::MatrixXd BuildAffinityMatrix(const Eigen::MatrixXd& centroids,
                                    const Eigen::MatrixXd& semantics,
                                    const SceneGraphConfig& config = {});

// Node similarity C (n x m) of §3.3: C_jk = 1 + cos(s^p_j, s^q_k), in [0, 2]. Throws InputError
// when the semantic dimensions differ or values are not finite.
Eigen::MatrixXd NodeSimilarity(const Eigen::MatrixXd& semantics_source,
                               const Eigen::MatrixXd& semantics_target);

// C with an appearance term (docs/MATCHING.md):
//   C_jk = 1 + cos(s^p_j, s^q_k) - lambda (1 - A_jk)  where comparable(j, k), else the C above,
// A (n x m) the appearance cosines, comparable (n x m, 0/1) whether both objects have descriptors
// of one kind. lambda = 0 gives NodeSimilarity exactly. Throws InputError for wrong sizes,
// non-finite values or lambda < 0.
Eigen::MatrixXd NodeSimilarity(const Eigen::MatrixXd& semantics_source,
                               const Eigen::MatrixXd& semantics_target,
                               const Eigen::MatrixXd& appearance_cosine,
                               const Eigen::MatrixXd& comparable, double appearance_weight);

}  // namespace zeroreg
