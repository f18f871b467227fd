// Internal helpers: values from untrusted input as they appear in messages. An error or warning
// echoes what it was given, but never a megabyte label or a 770-digit number, and never an
// invisible character the reader cannot see ("'585' is not a number" when the token is a byte
// order mark followed by 585).
#pragma once

#include <string>

namespace zeroreg::detail {

// Longest text echoed whole; longer text is cut (kept at both ends) and its length stated.
constexpr size_t kMaxShownChars = 80;

// `text` for a message: control characters and invisible Unicode characters (byte order mark,
// no-break and zero-width spaces, ...) written as <U+FEFF>, bytes that are not UTF-8 as <0xNN>,
// and text longer than kMaxShownChars cut in the middle with "... (N bytes) ...".
std::string ShownText(const std::string& text);

// The invisible characters of `text` named, e.g. "U+FEFF (byte order mark)", comma-separated;
// empty when it holds none.
std::string InvisibleCharacters(const std::string& text);

// A number for a message: at most 7 significant digits (1e+300, not 301 digits), "inf", "nan".
std::string ShownNumber(double value);

}  // namespace zeroreg::detail
