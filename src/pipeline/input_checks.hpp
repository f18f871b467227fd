// Boundary checks of what callers (C++ or Python) hand the pipeline: the core trusts its inputs,
// so scans and motion priors are checked once, here, with messages that name the scan and view.
#pragma once

#include <optional>
#include <string>

#include "zeroreg/register.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// InputError naming `role` ("source", "target") and the view when a view's images, depth or
// intrinsics are unusable.
void CheckScan(const Scan& scan, const std::string& role);

// InputError when the prior is not a rigid transform or its tolerances are not positive numbers
// (rather than silently making every result invalid).
void CheckPrior(const std::optional<MotionPrior>& prior);

}  // namespace zeroreg
