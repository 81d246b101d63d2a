// io/messages: whatever text an error quotes (a 20 MB line, binary bytes, a
// NUL, several lines), the message is one printable line of bounded length
// that keeps its start (the key or file) and its end (the reason).
#include <doctest/doctest.h>

#include <string>

#include "io/messages.hpp"
#include "io_test_support.hpp"

using namespace slipstrip;
using io_test::contains;

namespace {

bool printable_one_line(const std::string& text) {
  for (unsigned char c : text)
    if (c < 0x20 || c == 0x7F) return false;
  return true;
}

}  // namespace

TEST_CASE("short printable text is unchanged, UTF-8 included") {
  CHECK(io::one_line("geometry.nodes = 3 is out of range") == "geometry.nodes = 3 is out of range");
  CHECK(io::one_line("Scholz µ = 9 GPa, Ω") == "Scholz µ = 9 GPa, Ω");
}

TEST_CASE("control characters, NUL and invalid UTF-8 are escaped, not cut or passed through") {
  const std::string nul_inside = std::string("line 3: 'ab") + '\0' + "cd' is not one finite number";
  const std::string out = io::one_line(nul_inside);
  CHECK(out == "line 3: 'ab\\0cd' is not one finite number");
  CHECK(io::one_line("a\nb\r\tc\x1b[31m") == "a\\nb\\r\\tc\\x1b[31m");
  // UTF-16 (a BOM and bytes that are not UTF-8), a lone continuation byte, an
  // overlong encoding and a surrogate are shown byte by byte.
  CHECK(io::one_line("\xff\xfe" "1\x00", 64) == "\\xff\\xfe1");
  CHECK(io::one_line(std::string("\xff\xfe" "1\0", 4)) == "\\xff\\xfe1\\0");
  CHECK(io::one_line("\x80x\xc0\xafy\xed\xa0\x80") == "\\x80x\\xc0\\xafy\\xed\\xa0\\x80");
  // Unicode line separators and C1 controls would break or hide a line too.
  CHECK(io::one_line("a\u2028b\u0085c\u202Ed") == "a\\u2028b\\u0085c\\u202ed");
}

TEST_CASE("a 20 MB input keeps the message's start and reason and stays within the limit") {
  const std::string huge(20 << 20, '7');
  const std::string message = "friction.a = {...}: node file 'a.txt' line 1: '" + huge + "x' is not one finite number";
  const std::string out = io::one_line(message);
  CHECK(out.size() <= io::kMaxMessageChars);
  CHECK(printable_one_line(out));
  CHECK(out.rfind("friction.a = {...}: node file 'a.txt' line 1: '777", 0) == 0);
  CHECK(contains(out, "x' is not one finite number"));
  CHECK(contains(out, " bytes omitted] ... "));
  // The count is what is missing: shown head and tail plus the omitted bytes make the input.
  const auto open = out.find(" ... [") + 6, close = out.find(" bytes omitted]");
  const std::size_t omitted = std::stoull(out.substr(open, close - open));
  const std::size_t shown = out.size() - (out.find("] ... ") + 6 - out.find(" ... ["));
  CHECK(omitted + shown == message.size());
}

TEST_CASE("truncation never splits a UTF-8 character or an escape") {
  for (std::size_t limit : {64u, 65u, 66u, 67u, 100u, 101u, 102u, 103u}) {
    const std::string greek = std::string(300, 'a') + std::string(200, '\x01') + "λλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλλ";
    const std::string out = io::one_line(greek, limit);
    CHECK(out.size() <= limit);
    CHECK(printable_one_line(out));
    // Every escape is complete (\x then two hex digits) and the text is valid UTF-8 (λ whole).
    for (std::size_t k = out.find("\\x"); k != std::string::npos; k = out.find("\\x", k + 1)) {
      REQUIRE(k + 3 < out.size());
      CHECK(std::isxdigit(static_cast<unsigned char>(out[k + 2])));
      CHECK(std::isxdigit(static_cast<unsigned char>(out[k + 3])));
    }
    CHECK(out.back() != '\xce');  // λ is \xce\xbb: never the first byte alone at the end
    const auto lambda_bytes = out.find("\xbb");
    CHECK((lambda_bytes == std::string::npos || (lambda_bytes > 0 && out[lambda_bytes - 1] == '\xce')));
  }
}

TEST_CASE("quoted_input bounds one piece of input inside a longer message") {
  const std::string q = io::quoted_input(std::string(5000, 'z') + "\n", 80);
  CHECK(q.size() <= 82);
  CHECK(q.front() == '\'');
  CHECK(q.back() == '\'');
  CHECK(contains(q, "\\n"));
}
