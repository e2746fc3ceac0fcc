// Text for HTML, SVG and XML files octrace writes (the explain page, the slide figures, the
// regression report): user text such as scene names and paths goes in escaped.
#pragma once

#include <string>

namespace oct {

// `text` with &, <, > and " escaped, fit for an element's text or a quoted attribute.
std::string xmlEscape(const std::string& text);

}  // namespace oct
