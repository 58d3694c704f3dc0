// The viewer page of web/ (web/src/report.html with the bundled script inlined), compiled into the
// library at build time (web/build.mjs). The data of a run replaces the placeholder
// __FLATMORPH_DATA__ (JSON) and __FLATMORPH_TITLE__ (HTML text).
#pragma once

#include <string_view>

namespace flatmorph {

std::string_view viewer_html_template();

}  // namespace flatmorph
