#pragma once
// What every error message becomes before it reaches a user: one line,
// printable, and bounded in length, whatever input it quotes (a 20 MB line of
// a node file, binary garbage, a NUL byte, a multi-line TOML value).
#include <cstddef>
#include <string>
#include <string_view>

namespace slipstrip::io {

// The longest message one_line() lets through [characters].  A few terminal
// lines: long enough for a key, a path, a quoted value and the reason.
inline constexpr std::size_t kMaxMessageChars = 400;

// `text` as one printable line of at most `max_chars` bytes.
//  * Valid UTF-8 is kept (names and paths in any language); control
//    characters become escapes (\n, \r, \t, \0, \xNN; C1 controls and the
//    Unicode line and paragraph separators \u0085, \u2028, ...), and so does
//    every byte that is not part of valid UTF-8 (\xNN).
//  * A longer text keeps its head (about 3/5) and its tail (about 2/5) with
//    " ... [N bytes omitted] ... " between them: a message names the key or
//    the file at its start and the reason at its end, and both survive.
// The result never splits a UTF-8 character or an escape.  max_chars below
// 64 is raised to 64 (room for the marker and something on either side).
std::string one_line(std::string_view text, std::size_t max_chars = kMaxMessageChars);

// A piece of input quoted inside a message: '...' around one_line(text,
// max_chars), so one line of a node file or one config value never takes
// over the message.
std::string quoted_input(std::string_view text, std::size_t max_chars = 80);

}  // namespace slipstrip::io
