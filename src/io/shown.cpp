#include "io/shown.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace zeroreg::detail {
namespace {

struct CodePoint {
  std::uint32_t value = 0;
  size_t length = 1;  // bytes
  bool valid = false;
};

// The UTF-8 sequence starting at `text[i]` (invalid: a lone byte).
CodePoint DecodeAt(const std::string& text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  CodePoint cp;
  if (b0 < 0x80) return {b0, 1, true};
  size_t length = 0;
  std::uint32_t value = 0;
  if ((b0 & 0xE0) == 0xC0) {
    length = 2;
    value = b0 & 0x1F;
  } else if ((b0 & 0xF0) == 0xE0) {
    length = 3;
    value = b0 & 0x0F;
  } else if ((b0 & 0xF8) == 0xF0) {
    length = 4;
    value = b0 & 0x07;
  } else {
    return cp;
  }
  if (i + length > text.size()) return cp;
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return cp;
    value = (value << 6) | (byte(i + k) & 0x3F);
  }
  static const std::uint32_t kMinimum[] = {0, 0, 0x80, 0x800, 0x10000};
  if (value < kMinimum[length] || value > 0x10FFFF || (value >= 0xD800 && value <= 0xDFFF)) {
    return cp;
  }
  return {value, length, true};
}

// The name of an invisible or blank-looking character, or nullptr for one that shows.
const char* InvisibleName(std::uint32_t c) {
  switch (c) {
    case 0xFEFF:
      return "byte order mark";
    case 0x00A0:
      return "no-break space";
    case 0x00AD:
      return "soft hyphen";
    case 0x200B:
      return "zero-width space";
    case 0x200C:
      return "zero-width non-joiner";
    case 0x200D:
      return "zero-width joiner";
    case 0x2060:
      return "word joiner";
    case 0x202F:
      return "narrow no-break space";
    case 0x3000:
      return "ideographic space";
    case 0xFFFD:
      return "replacement character";
    default:
      break;
  }
  if (c < 0x20 || c == 0x7F || (c >= 0x80 && c < 0xA0)) return "control character";
  if ((c >= 0x2000 && c <= 0x200F) || (c >= 0x2028 && c <= 0x202E) ||
      (c >= 0x2066 && c <= 0x2069)) {
    return "invisible space or direction mark";
  }
  return nullptr;
}

std::string Hex(std::uint32_t value, int digits) {
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "%0*X", digits, static_cast<unsigned>(value));
  return buffer;
}

// Every character of `text` made visible (no cutting).
std::string Escape(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const CodePoint cp = DecodeAt(text, i);
    if (!cp.valid) {
      out += "<0x" + Hex(static_cast<unsigned char>(text[i]), 2) + ">";
      i += 1;
      continue;
    }
    if (InvisibleName(cp.value) != nullptr && cp.value != ' ') {
      out += "<U+" + Hex(cp.value, 4) + ">";
    } else {
      out.append(text, i, cp.length);
    }
    i += cp.length;
  }
  return out;
}

// The first `count` bytes of `text`, not splitting a UTF-8 sequence.
size_t CutBefore(const std::string& text, size_t count) {
  while (count > 0 && count < text.size() &&
         (static_cast<unsigned char>(text[count]) & 0xC0) == 0x80)
    --count;
  return count;
}
size_t CutAfter(const std::string& text, size_t from) {
  while (from < text.size() && (static_cast<unsigned char>(text[from]) & 0xC0) == 0x80) ++from;
  return from;
}

}  // namespace

std::string ShownText(const std::string& text) {
  if (text.size() <= kMaxShownChars) return Escape(text);
  const size_t head = CutBefore(text, kMaxShownChars / 2);
  const size_t tail = CutAfter(text, text.size() - kMaxShownChars / 4);
  return Escape(text.substr(0, head)) + "... (" + std::to_string(text.size()) +
         " bytes in all) ..." + Escape(text.substr(tail));
}

std::string InvisibleCharacters(const std::string& text) {
  std::vector<std::uint32_t> seen;
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const CodePoint cp = DecodeAt(text, i);
    i += cp.length;
    const char* name = cp.valid ? InvisibleName(cp.value) : "a byte that is not UTF-8";
    if (name == nullptr || (cp.valid && cp.value == ' ')) continue;
    const std::uint32_t key = cp.valid ? cp.value : 0xFFFFFFFF;
    bool known = false;
    for (std::uint32_t s : seen) known = known || s == key;
    if (known) continue;
    seen.push_back(key);
    out += (out.empty() ? "" : ", ") +
           (cp.valid ? "U+" + Hex(cp.value, 4) + " (" + name + ")" : std::string(name));
  }
  return out;
}

std::string ShownNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.7g", value);
  return buffer;
}

}  // namespace zeroreg::detail
