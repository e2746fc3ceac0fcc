// The JSON an explain page carries in <script id="octrace-data" type="application/json">, or ""
// (one definition for the unity builds, see tests/paths.h).
#pragma once

#include <string>

namespace octtest {

inline std::string dataOf(const std::string& page) {
    const std::string open = "<script id=\"octrace-data\" type=\"application/json\">";
    const size_t a = page.find(open);
    const size_t b = page.find("</script>", a);
    if (a == std::string::npos || b == std::string::npos) return "";
    return page.substr(a + open.size(), b - a - open.size());
}

}  // namespace octtest
