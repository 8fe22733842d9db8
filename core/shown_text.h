#pragma once
#include <string>
#include <string_view>

namespace fscil {

// Text from a file or the command line as an error message may show it: one short line of
// printable characters. A byte-order mark, a carriage return or any other invisible or invalid
// byte is spelled out (\ufeff, \r, \x00), so "got 'x', expected 'x'" never shows two
// identical-looking strings, and a long field is cut (after 80 characters by default) with its size.
std::string shown_text(std::string_view text, std::size_t max_characters = 80);
// Whether `text` holds no control character (no line break, tab, NUL or DEL): one line a table,
// a CSV field or a footnote can carry as it is.
bool is_one_line(std::string_view text);

}  // namespace fscil
