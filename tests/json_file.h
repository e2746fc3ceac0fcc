// Reading a JSON file in a test (one definition for the unity builds, see tests/paths.h).
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace octtest {

// Json: nlohmann::json (keys sorted), or nlohmann::ordered_json to keep the file's key order.
template <class Json = nlohmann::json>
Json readJson(const std::filesystem::path& p) {
    std::ifstream in(p);
    return Json::parse(in);
}

}  // namespace octtest
