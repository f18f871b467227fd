// A pair list folder (the format of ../shared/lists, docs/EVAL.md "eval pairs --list"):
//
//   pairs.txt  optional "# kind: frames", other '#' comment lines, then one "i j" per line
//   gt.log     3DMatch .log: header "i j n", then the 4x4 T_i_j mapping frame j into frame i
//
// Target = frame i, source = frame j, ground truth = the gt.log matrix (not the dataset poses).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/records.hpp"

namespace zeroreg {

struct PairList {
  std::string dir;              // as given
  std::string name;             // the folder's name, e.g. "hololens-gap1"; the tasks' benchmark
  std::string scene;            // "# scene: NAME" of pairs.txt, empty if absent
  std::vector<PairTask> tasks;  // pairs.txt order
  // What decides the list's content, for run.json settings: the folder's name and the SHA-256
  // of pairs.txt and gt.log (a resumed folder refuses another list).
  nlohmann::json settings;
};

// Reads `<dir>/pairs.txt` and `<dir>/gt.log` and pairs them up by (i, j) (gt.log may list them in
// another order). Every frame id must be in `frame_ids` (sorted; the ids of --data). Refs are
// "<dataset_root>@<id>", scene = `scene`. Throws InputError naming the file (and line) for a
// missing file, a malformed line, a duplicate pair, a pair of pairs.txt without a gt.log entry, a
// gt.log entry not in pairs.txt, a non-rigid gt.log matrix, or an id missing from the data.
PairList ReadPairList(const std::string& dir, const std::vector<int>& frame_ids,
                      const std::string& dataset_root, const std::string& scene);

}  // namespace zeroreg
