#include "eval/pair_list.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "io/shown.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

struct ListedPair {
  int i = 0, j = 0, line = 0;
};

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::string PairText(int i, int j) { return "pair " + std::to_string(i) + " " + std::to_string(j); }

// pairs.txt: comments (with the optional "# kind: frames" and "# scene: NAME" keys), then "i j".
std::vector<ListedPair> ReadListedPairs(const std::string& path, std::string* scene) {
  detail::RequireFile(path, "pair list pairs.txt");  // also refuses a FIFO, which would block
  std::ifstream in(path);
  if (!in) {
    throw MakeInputError(path,
                         "cannot open the pair list; expected a list folder holding "
                         "pairs.txt (\"i j\" per line) and gt.log");
  }
  std::vector<ListedPair> pairs;
  std::map<std::pair<int, int>, int> seen;
  int number = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++number;
    const std::string line = Trim(raw);
    const std::string where = path + " line " + std::to_string(number);
    if (line.empty()) continue;
    if (line[0] == '#') {
      const std::string body = Trim(line.substr(1));
      const size_t colon = body.find(':');
      if (colon == std::string::npos) continue;
      const std::string key = Trim(body.substr(0, colon)), value = Trim(body.substr(colon + 1));
      if (key == "kind" && value != "frames") {
        throw MakeInputError(where, "'" + detail::ShownText(line) + "': this list holds '" +
                                        detail::ShownText(value) +
                                        "' pairs; eval pairs --list reads frame pairs "
                                        "(\"# kind: frames\")");
      }
      if (key == "scene") *scene = value;
      continue;
    }
    std::istringstream fields(line);
    long long i = -1, j = -1;
    std::string rest;
    if (!(fields >> i >> j) || (fields >> rest) || i < 0 || j < 0 || i > 1000000000 ||
        j > 1000000000) {
      throw MakeInputError(where, "'" + detail::ShownText(line) +
                                      "'; expected two non-negative integers \"i j\" "
                                      "(target frame i, source frame j) or a '#' comment");
    }
    const auto key = std::make_pair(static_cast<int>(i), static_cast<int>(j));
    const auto [it, inserted] = seen.emplace(key, number);
    if (!inserted) {
      throw MakeInputError(where, PairText(key.first, key.second) +
                                      " is listed twice (first on line " +
                                      std::to_string(it->second) + ")");
    }
    pairs.push_back({key.first, key.second, number});
  }
  if (pairs.empty()) throw MakeInputError(path, "lists no pair; expected lines \"i j\"");
  return pairs;
}

// Rigid up to the rounding of real ground truth (7-Scenes poses deviate from orthonormal by up to
// 2e-4; the metrics orthonormalise the GT rotation): a scaled or sheared matrix is refused.
void CheckRigid(const LogEntry& e, const std::string& path) {
  const Eigen::Matrix3d R = e.T_i_j.topLeftCorner<3, 3>();
  const double orthogonality =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const Eigen::RowVector4d last = e.T_i_j.row(3);
  if (orthogonality > 1e-2 || R.determinant() < 0 ||
      (last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
    throw MakeInputError(path + " line " + std::to_string(e.line),
                         "the matrix of " + PairText(e.i, e.j) +
                             " is not a rigid transform (rotation not orthonormal, or last row "
                             "not 0 0 0 1)");
  }
}

}  // namespace

PairList ReadPairList(const std::string& dir, const std::vector<int>& frame_ids,
                      const std::string& dataset_root, const std::string& scene) {
  if (!fs::is_directory(dir)) {
    throw MakeInputError("--list " + dir,
                         "is not a folder; expected a list folder holding "
                         "pairs.txt and gt.log (see ../shared/lists)");
  }
  PairList list;
  list.dir = dir;
  fs::path folder = fs::path(dir).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();
  list.name = folder.filename().string();
  const std::string pairs_path = (fs::path(dir) / "pairs.txt").string();
  const std::string log_path = (fs::path(dir) / "gt.log").string();
  const std::vector<ListedPair> listed = ReadListedPairs(pairs_path, &list.scene);
  if (!fs::is_regular_file(log_path)) {
    throw MakeInputError(log_path,
                         "not found; a list folder holds the ground truth of pairs.txt "
                         "in gt.log (3DMatch .log format)");
  }
  const std::vector<LogEntry> log = ReadLogFile(log_path);

  std::map<std::pair<int, int>, const LogEntry*> gt;
  std::map<std::pair<int, int>, int> listed_line;
  for (const ListedPair& p : listed) listed_line[{p.i, p.j}] = p.line;
  for (const LogEntry& e : log) {
    const std::string where = log_path + " line " + std::to_string(e.line);
    const auto [it, inserted] = gt.emplace(std::make_pair(e.i, e.j), &e);
    if (!inserted) {
      throw MakeInputError(where, PairText(e.i, e.j) + " has a second entry (first on line " +
                                      std::to_string(it->second->line) + ")");
    }
    if (listed_line.find({e.i, e.j}) == listed_line.end()) {
      throw MakeInputError(where, PairText(e.i, e.j) + " is not in " + pairs_path +
                                      "; gt.log must hold exactly the pairs of pairs.txt");
    }
    CheckRigid(e, log_path);
  }
  auto has = [&](int id) { return std::binary_search(frame_ids.begin(), frame_ids.end(), id); };
  for (const ListedPair& p : listed) {
    const std::string where = pairs_path + " line " + std::to_string(p.line);
    const auto it = gt.find({p.i, p.j});
    if (it == gt.end()) {
      throw MakeInputError(where, PairText(p.i, p.j) + " has no ground truth in " + log_path +
                                      " (expected an entry with header \"" + std::to_string(p.i) +
                                      " " + std::to_string(p.j) + " n\")");
    }
    for (const int id : {p.i, p.j}) {
      if (!has(id)) {
        throw MakeInputError(where, PairText(p.i, p.j) + ": frame " + std::to_string(id) +
                                        " is not in --data " + dataset_root +
                                        " (wrong --data for this list?)");
      }
    }
    PairTask t;
    t.benchmark = list.name;
    t.scene = scene;
    t.target_id = p.i;
    t.source_id = p.j;
    t.target_ref = dataset_root + "@" + std::to_string(p.i);
    t.source_ref = dataset_root + "@" + std::to_string(p.j);
    t.T_target_source_gt = it->second->T_i_j;  // gt.log "i j" maps frame j (source) into i
    t.log_n = it->second->n;
    list.tasks.push_back(t);
  }
  list.settings = {{"name", list.name},
                   {"pairs_txt_sha256", Sha256OfFile(pairs_path)},
                   {"gt_log_sha256", Sha256OfFile(log_path)}};
  return list;
}

}  // namespace zeroreg
