// Is the source a mirror image of the target? No rigid motion maps a scene onto its mirror image,
// yet a room or a box is close to mirror-symmetric in depth, and the geometric check (src/verify)
// accepts a mirrored scan fitted to it (27 frames of three scenes flipped left-right:
// scripts/bench-mirrored.py). The image descriptors (XFeat, SIFT) are not mirror-invariant, so the
// images themselves tell: a scan's images share many distinctive matches with the other scan's
// images of the same surfaces, and few once flipped left-right; a mirror image the other way round.
#pragma once

#include <vector>

#include "estimate/lift.hpp"
#include "features/feature_extractor.hpp"
#include "pipeline/image_correspondences.hpp"
#include "pipeline/prepared.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// The features of each view's colour image flipped left-right, keypoints in the view's own
// pixels and lifted with its depth (`lifts`: per view, as the unflipped ones were).
std::vector<LiftedFeatures> ExtractMirroredFeatures(const FeatureExtractor& extractor,
                                                    const Scan& scan,
                                                    const std::vector<ViewLift>& lifts);

// Distinctive matches (ViewOverlapScore) of the source's views with the target's, as given and
// with the source's images flipped left-right: per source view the best target view's, summed.
struct Handedness {
  int as_given = 0;
  int mirrored = 0;
};
int DistinctiveMatches(const std::vector<LiftedFeatures>& source,
                       const std::vector<LiftedFeatures>& target);

// The images as given share at least this many distinctive matches: the mirror test is not run
// (a flipped frame shared 1-22 with the frame it was flipped from, on the three scenes; the
// mirrored images would need more than verify.mirror_ratio times this).
constexpr int kMirrorTestBelow = 50;

// Whether the source looks like a mirror image of the target (VerifyConfig::mirror_min_matches,
// mirror_ratio; never with mirror_min_matches 0).
bool LooksMirrored(const Handedness& h, const VerifyConfig& config);
// What the mirrored matches must reach to be a mirror image (the refusal's threshold).
double MirrorThreshold(const Handedness& h, const VerifyConfig& config);

// A valid *r becomes not valid (refusal kMirrorImage) when the source looks like a mirror image
// of the target. The flipped features are made once per source scan (Prepared::mirrored) and only
// where the test runs: verification on, r valid, the images as given below kMirrorTestBelow.
void RefuseMirrorImage(const Prepared& source, const Prepared& target,
                       const FeatureExtractor* extractor, const VerifyConfig& config,
                       RegistrationResult* r);

}  // namespace zeroreg
