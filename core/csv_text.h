#pragma once
#include <string>
#include <vector>

namespace fscil {

// The one CSV reader, for the files we write and for datasets' tables.
// The lines of a CSV file as a spreadsheet may also save it: a byte-order mark before the first
// line and a carriage return before each line end are not part of any line. (A quoted field may
// not hold a line break.)
std::vector<std::string> csv_lines(const std::string& text);
// The fields of one line, split at commas outside double quotes (RFC 4180: a field that starts
// with a quote runs to its closing quote, "" inside is one quote; a quote elsewhere is a
// character); blanks around each field are dropped. A trailing comma gives an empty last field.
std::vector<std::string> csv_fields(const std::string& line);
// The one CSV field writer: `text` in double quotes, a quote doubled, when it holds a comma, a quote
// or a line break (RFC 4180); as it is otherwise. csv_fields reads it back (blanks at its ends aside,
// which the reader drops), except a line break, which csv_lines splits: writers keep them out.
std::string csv_field(const std::string& text);
// `text` without the blanks (spaces, tabs, line ends) around it.
std::string trimmed(const std::string& text);

}  // namespace fscil
