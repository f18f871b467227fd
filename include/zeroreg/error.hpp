// Errors raised where inputs enter zeroreg (files, CLI, Python).
//
// The core never throws for a registration that merely failed: that is reported through
// RegistrationResult::valid / reason. InputError is for input that cannot be used at all, and its
// message always names the file or argument, what was wrong and what was expected.
#pragma once

#include <stdexcept>
#include <string>

namespace zeroreg {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Builds "<where>: <problem>" so that every message starts with the offending file or argument.
inline InputError MakeInputError(const std::string& where, const std::string& problem) {
  return InputError(where + ": " + problem);
}

}  // namespace zeroreg
