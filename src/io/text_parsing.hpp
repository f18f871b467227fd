// Internal helpers of src/io: reading whitespace-separated numbers from small text files and
// validating the matrices they hold. Every failure is an InputError naming the file.
#pragma once

#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg::detail {

// Throws InputError "<path>: <what> not found" unless `path` is an existing regular file.
void RequireFile(const std::string& path, const std::string& what);

// Parses a whitespace-separated token as a double (accepts "inf"/"nan", which callers reject or
// interpret). Returns false if the token is not entirely a number.
bool ParseDouble(const std::string& token, double* value);

// All numbers of a small text file, in order. A token that is not a number is an InputError
// naming the file, the line and the token. A missing file is an InputError naming `what`.
std::vector<double> ReadNumbers(const std::string& path, const std::string& what);

// Interprets 16 row-major numbers as a rigid transform and checks it: finite, last row 0 0 0 1,
// rotation orthonormal within 1e-2 with determinant +1. `where` starts the error message.
Transform RigidFromNumbers(const std::vector<double>& numbers, const std::string& where);

// Checks that an already built 4x4 matrix is a rigid transform (same rules as above).
void CheckRigid(const Transform& T, const std::string& where);

// Checks a depth scale argument (raw units per metre): finite and > 0.
void CheckDepthScale(double depth_scale, const std::string& where);

// Joins `path` to `base_dir` unless it is absolute (descriptor-relative paths).
std::string ResolvePath(const std::string& base_dir, const std::string& path);

}  // namespace zeroreg::detail
