// Pair lists of the two protocols (DESIGN §6) and the selection steps of the runner: --pairs,
// --limit, --shard. Selection order: protocol list -> --pairs filter -> --limit -> --shard, so
// the shards of a run partition exactly the pairs a single run would evaluate.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "eval/records.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

// ---- 3DMatch / 3DLoMatch from RGB-D --------------------------------------------------------

// Fragment k = frames first..first+frames_per_fragment-1 with first = k * frames_per_fragment.
// Returns the k whose frames are all in `frame_ids` (sorted), in increasing order.
std::vector<int> AvailableFragments(const std::vector<int>& frame_ids, int frames_per_fragment);

// Every pair "i j" of `<gt_root>/<benchmark>/<scene>/gt.log` (with gt.info) whose fragments are
// both in `available`, in gt.log order: target = fragment i, source = fragment j, ground truth
// T_i_j, consecutive = (j == i + 1). Refs are left empty (the caller knows where fragments live).
// Throws InputError when gt.log or gt.info is missing or they disagree.
std::vector<PairTask> ThreeDMatchTasks(const std::string& gt_root, const std::string& benchmark,
                                       const std::string& scene, const std::vector<int>& available);

// ---- frame pairs -------------------------------------------------------------------------------

// Pairs (i, i + gap) for i = first, first + step, ... with both frames in `frame_ids`: target =
// frame i, source = frame i + gap. benchmark "frames-g<gap>", scene = `scene`, refs
// "<dataset_root>@<id>". Throws InputError on gap < 1 or step < 1.
std::vector<PairTask> FramePairTasks(const std::vector<int>& frame_ids, int gap, int step,
                                     int first, const std::string& dataset_root,
                                     const std::string& scene);

// ---- selection ---------------------------------------------------------------------------------

// A --pairs file: one pair per line, "i j" = target i, source j (as in gt.log); blank lines and
// lines starting with '#' are skipped. Throws InputError naming the file and line.
std::vector<std::pair<int, int>> ReadPairsFile(const std::string& path);

// Keeps the tasks whose (target, source) is listed, in task order. Every listed pair must match
// at least one task, else InputError naming `where` and the pair.
std::vector<PairTask> FilterPairs(const std::vector<PairTask>& tasks,
                                  const std::vector<std::pair<int, int>>& pairs,
                                  const std::string& where);

struct Shard {
  int index = 0;  // 0-based
  int count = 1;
};
// "i/N" with 0 <= i < N. Throws InputError otherwise.
Shard ParseShard(const std::string& text);
// Task k goes to shard k % N (round robin: shards get similar mixes of easy and hard pairs).
std::vector<PairTask> ApplyShard(const std::vector<PairTask>& tasks, const Shard& shard);

}  // namespace zeroreg
