// Comma lists of names (--set, --accel, --backend and their Python spellings): the one parser.
#pragma once

#include <string>
#include <vector>

namespace oct {

// Splits a comma list, trimming spaces and tabs around each item and dropping empty ones.
std::vector<std::string> splitList(const std::string& text);

}  // namespace oct
