#include "semantics/label_aliases.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace zeroreg {

std::string CocoSpelling(const std::string& label) {
  // VOC (and the hpc203 coco.names) -> COCO-2017 (cocodataset.org category names).
  static const std::array<std::pair<const char*, const char*>, 6> kVocToCoco = {{
      {"aeroplane", "airplane"},
      {"motorbike", "motorcycle"},
      {"sofa", "couch"},
      {"pottedplant", "potted plant"},
      {"diningtable", "dining table"},
      {"tvmonitor", "tv"},
  }};
  std::string lower = label;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const auto& [voc, coco] : kVocToCoco) {
    if (lower == voc) return coco;
  }
  return label;
}

}  // namespace zeroreg
