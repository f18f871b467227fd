// Category spellings. COCO-80 detectors ship different name lists: YOLOX uses the COCO-2017
// spellings ("dining table"), the PicoDet export the PASCAL-VOC ones ("diningtable"). Everything
// downstream (label equality in the association and the label filter of §3.3, the CLIP table
// lookup of §3.2, the ensemble's per-class NMS) compares labels as strings, so every built-in
// detector reports the COCO-2017 spelling.
#pragma once

#include <string>

namespace zeroreg {

// The COCO-2017 spelling of a COCO-80 class name: the six VOC spellings (aeroplane, motorbike,
// sofa, pottedplant, diningtable, tvmonitor; case-insensitive) map to airplane, motorcycle,
// couch, potted plant, dining table, tv. Any other label is returned unchanged.
std::string CocoSpelling(const std::string& label);

}  // namespace zeroreg
