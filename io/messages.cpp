#include "io/messages.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace slipstrip::io {
namespace {

// One source character (or one invalid byte) and how it is shown.
struct Unit {
  std::size_t source_bytes;
  std::string shown;
};

std::string hex_byte(unsigned char byte) {
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "\\x%02x", byte);
  return buffer;
}

// Length of the valid UTF-8 sequence at text[i] and its code point; 0 if the
// bytes there are not one (overlong forms, surrogates and values above
// U+10FFFF are invalid, as in the standard).
std::size_t utf8_sequence(std::string_view text, std::size_t i, std::uint32_t& code_point) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  std::size_t length;
  std::uint32_t minimum;
  if (lead < 0x80) {
    code_point = lead;
    return 1;
  } else if ((lead & 0xE0) == 0xC0) {
    length = 2, minimum = 0x80, code_point = lead & 0x1F;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3, minimum = 0x800, code_point = lead & 0x0F;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4, minimum = 0x10000, code_point = lead & 0x07;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code_point = (code_point << 6) | (byte(i + k) & 0x3F);
  }
  if (code_point < minimum || code_point > 0x10FFFF || (code_point >= 0xD800 && code_point <= 0xDFFF))
    return 0;
  return length;
}

Unit unit_at(std::string_view text, std::size_t i) {
  std::uint32_t cp = 0;
  const std::size_t length = utf8_sequence(text, i, cp);
  if (length == 0) return {1, hex_byte(static_cast<unsigned char>(text[i]))};
  if (length == 1) {
    switch (cp) {
      case '\n': return {1, "\\n"};
      case '\r': return {1, "\\r"};
      case '\t': return {1, "\\t"};
      case '\0': return {1, "\\0"};
      default: break;
    }
    if (cp < 0x20 || cp == 0x7F) return {1, hex_byte(static_cast<unsigned char>(cp))};
    return {1, std::string(1, static_cast<char>(cp))};
  }
  // C1 controls (NEL among them), line/paragraph separators, and the
  // direction overrides that can make a terminal line lie about its content.
  const bool invisible = (cp >= 0x80 && cp <= 0x9F) || cp == 0x2028 || cp == 0x2029 ||
                         (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069) || cp == 0xFEFF;
  if (invisible) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(cp));
    return {length, buffer};
  }
  return {length, std::string(text.substr(i, length))};
}

// Units of text[begin, end) until `budget` shown bytes are used (or the end).
std::vector<Unit> units_forward(std::string_view text, std::size_t begin, std::size_t end, std::size_t budget) {
  std::vector<Unit> units;
  std::size_t shown = 0;
  for (std::size_t i = begin; i < end;) {
    Unit u = unit_at(text.substr(0, end), i);
    if (shown + u.shown.size() > budget) break;
    shown += u.shown.size();
    i += u.source_bytes;
    units.push_back(std::move(u));
  }
  return units;
}

}  // namespace

std::string one_line(std::string_view text, std::size_t max_chars) {
  max_chars = std::max<std::size_t>(max_chars, 64);
  // The whole text if it fits (an escape is at most 6 bytes per source byte,
  // so only texts within max_chars bytes are tried whole).
  if (text.size() <= max_chars) {
    auto all = units_forward(text, 0, text.size(), max_chars);
    std::size_t consumed = 0;
    for (const auto& u : all) consumed += u.source_bytes;
    if (consumed == text.size()) {
      std::string out;
      for (const auto& u : all) out += u.shown;
      return out;
    }
  }
  // Head and tail around a marker.  The marker's length depends on the count
  // it shows; 40 bytes hold it for any 64-bit count.
  const std::size_t marker_room = 40;
  const std::size_t room = max_chars - marker_room;
  const std::size_t head_budget = room * 3 / 5, tail_budget = room - head_budget;
  auto head = units_forward(text, 0, text.size(), head_budget);
  std::size_t head_bytes = 0;
  for (const auto& u : head) head_bytes += u.source_bytes;
  // The tail: start far enough back to fill its budget (every source byte
  // shows as at least one byte, so tail_budget source bytes are enough),
  // then move forward to the next character boundary.
  std::size_t tail_begin = std::max(head_bytes, text.size() > tail_budget ? text.size() - tail_budget : 0);
  for (int k = 0; k < 3 && tail_begin < text.size() &&
                  (static_cast<unsigned char>(text[tail_begin]) & 0xC0) == 0x80;
       ++k)
    ++tail_begin;
  auto tail = units_forward(text, tail_begin, text.size(), text.size());
  // Drop units from the front of the tail until it fits its budget.
  std::size_t tail_shown = 0;
  for (const auto& u : tail) tail_shown += u.shown.size();
  std::size_t drop = 0;
  while (tail_shown > tail_budget && drop < tail.size()) {
    tail_shown -= tail[drop].shown.size();
    tail_begin += tail[drop].source_bytes;
    ++drop;
  }
  std::string out;
  for (const auto& u : head) out += u.shown;
  out += " ... [" + std::to_string(tail_begin - head_bytes) + " bytes omitted] ... ";
  for (std::size_t k = drop; k < tail.size(); ++k) out += tail[k].shown;
  return out;
}

std::string quoted_input(std::string_view text, std::size_t max_chars) {
  // Appended piecewise: "'" + std::string + "'" trips GCC 12's false -Wrestrict.
  std::string out(1, '\'');
  out += one_line(text, max_chars);
  out += '\'';
  return out;
}

}  // namespace slipstrip::io
