// Text placed inside SVG and HTML documents the project writes.
#pragma once

#include <string>
#include <string_view>

namespace flatmorph {

// `text` with &, <, > and " replaced by their entities, safe inside XML/HTML elements and quoted
// attributes.
std::string xml_escape(std::string_view text);

}  // namespace flatmorph
