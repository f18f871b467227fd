// The HTML page of `zeroreg merge` / `zeroreg loops`: a top view of the keyframes before and after
// the optimisation, and the candidate pairs drawn as edges coloured by their verdict.
#pragma once

#include <string>

#include "zeroreg/recordings.hpp"

namespace zeroreg {

// `T_A_B_initial` places B's keyframes for the "before" view (B's own frame is arbitrary).
// Throws InputError when the file cannot be written.
void WriteRecordingsReport(const std::string& path, const RecordingsResult& result, bool merge,
                           const Transform& T_A_B_initial);

}  // namespace zeroreg
