#pragma once
#include <string>

namespace fscil {

// Text as the content or an attribute value of XML (SVG) or HTML: & < > " ' are escaped. A method,
// dataset or file name is not ours to trust, and one stray byte would make a whole SVG fail to
// load, so bytes that are not valid UTF-8 and control characters XML forbids become U+FFFD.
std::string xml_text(const std::string& text);

}  // namespace fscil
