// Internal helpers of src/io: reading whitespace-separated numbers from small text files and
// validating the matrices they hold. Every failure is an InputError naming the file.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg::detail {

// Throws InputError "<path>: <what> not found" unless `path` is an existing regular file.
void RequireFile(const std::string& path, const std::string& what);

// Parses the JSON file `path` (a regular file: a folder or a FIFO is refused rather than read or
// waited on). Any JSON error, including a number too large for a double (1e400), is an InputError
// naming the file and `what` ("config file", "scan descriptor", ...).
nlohmann::json ReadJsonFile(const std::string& path, const std::string& what);

// `json.dump(indent)` that never throws on text that is not UTF-8 (a path from a non-UTF-8 file
// system): such bytes are written as U+FFFD, so a result is never lost over a file name.
std::string DumpJson(const nlohmann::json& json, int indent = -1);

// Writes `text` to `path` through a temporary file in the same folder and a rename, so readers
// never see a partial file and a failure leaves any previous file intact. A link is kept: the file
// it names is replaced. An existing output that is not a regular file (a device such as /dev/null,
// a FIFO, /dev/stdout) is written into, never renamed over; a folder is refused. InputError on
// failure, with the system's reason ("No space left on device").
void WriteFileAtomically(const std::string& path, const std::string& text);

// A limit that the environment variable `name` may override (docs/FORMATS.md, "Limits"): its
// value when set (a finite number > 0, else InputError naming the variable), else `default_value`.
double LimitFromEnvironment(const char* name, double default_value);

// Parses a whitespace-separated token as a double (accepts "inf"/"nan", which callers reject or
// interpret). Returns false if the token is not entirely a number.
bool ParseDouble(const std::string& token, double* value);

// `line` without a leading UTF-8 byte order mark (the first line of a text file).
std::string WithoutByteOrderMark(const std::string& line);

// All numbers of a small text file, in order. A token that is not a number is an InputError
// naming the file, the line and the token (invisible characters in it named). A leading UTF-8 byte
// order mark is skipped. A missing file is an InputError naming `what`.
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
