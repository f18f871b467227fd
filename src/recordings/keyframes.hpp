// Keyframes of a recording: the frames that add view. A frame becomes a keyframe when the depth it
// shares with the last keyframe (its co-visibility, the rule of ../shared/lists/README.md: depth
// pixels of one frame moved into the other's camera by the poses, within a tolerance of the depth
// measured there, the smaller of the two directions) drops below a threshold. Later stages
// (place recognition, registration of loop-closure candidates) then work on a few frames per
// place instead of every frame of the sequence. Without poses for a frame or for the last
// keyframe, every k-th frame is a keyframe. Eigen and OpenCV core only.
#pragma once

#include <optional>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

struct KeyframeConfig {
  // A frame whose co-visibility with the last keyframe is below this becomes a keyframe, so every
  // frame shares at least this much depth with a keyframe. Measured on the three scenes of
  // ../shared/sessions (docs/RECORDINGS.md "Keyframes"): 0.7 keeps one frame in 21 on
  // redkitchen (Kinect) and about one in 2 on the HoloLens scene (ToF depth with holes, frames
  // about 8 cm apart), and gave the best place-recognition recall of 0.6, 0.7 and 0.8.
  double covisibility_threshold = 0.7;
  double depth_tolerance_m = 0.10;  // a point agrees when within this of the measured depth
  int pixel_stride = 4;             // depth pixels sampled on this grid (both axes)
  double min_depth_m = 0.1;         // depth outside [min, max] is ignored
  double max_depth_m = 8.0;
  // Without poses: every fallback_every-th frame after the last keyframe is one. 10 is twice as
  // often as the co-visibility rule at 0.7 picks on redkitchen and a fifth as often as on the
  // HoloLens scene (docs/RECORDINGS.md): a fixed step cannot fit both, so it errs towards more
  // keyframes on the Kinect-rate sequences.
  int fallback_every = 10;
};

// Throws InputError naming the field when a value is out of range.
void ValidateKeyframeConfig(const KeyframeConfig& config);

// Fraction of `a`'s sampled depth pixels that, moved into `b`'s camera by T_b_a (maps a's camera
// frame into b's), land inside b's image in front of it and within the tolerance of b's depth
// there. 0 when `a` has no valid depth. Views need depth (CV_32FC1, metres) and intrinsics.
double SeenFraction(const View& a, const View& b, const Transform& T_b_a,
                    const KeyframeConfig& config = {});

// The smaller of the two directions' SeenFraction, with camera-to-world poses of both views.
double Covisibility(const View& a, const Transform& T_world_a, const View& b,
                    const Transform& T_world_b, const KeyframeConfig& config = {});

// Chooses keyframes from frames given one at a time, in recording order. Keeps only the last
// keyframe's depth and pose, so a long recording needs no more memory than one frame.
class KeyframeSelector {
 public:
  explicit KeyframeSelector(const KeyframeConfig& config = {});  // validates it
  // Whether `frame` is a keyframe. The first frame always is. With a pose for this frame and for
  // the last keyframe: when their co-visibility is below the threshold; otherwise when
  // fallback_every frames have passed since the last keyframe. The pose is camera -> world
  // (odometry or ground truth; any fixed world frame).
  bool Add(const View& frame, const std::optional<Transform>& T_world_camera);
  // The co-visibility computed for the last frame given to Add (nullopt when none was computed:
  // the first frame, or a fallback decision).
  std::optional<double> last_covisibility() const { return last_covisibility_; }
  int frames_seen() const { return frames_seen_; }

 private:
  KeyframeConfig config_;
  int frames_seen_ = 0;
  int since_keyframe_ = 0;  // frames since the last keyframe
  View keyframe_;           // its depth and intrinsics only
  std::optional<Transform> keyframe_pose_;
  std::optional<double> last_covisibility_;
};

// All at once: the indices (into `frames`) of the keyframes. `poses` is empty (no poses: every
// fallback_every-th frame) or has one entry per frame.
std::vector<int> SelectKeyframes(const std::vector<View>& frames,
                                 const std::vector<std::optional<Transform>>& poses,
                                 const KeyframeConfig& config = {});

}  // namespace zeroreg
