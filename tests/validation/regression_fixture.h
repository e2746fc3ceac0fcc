// A copy of the committed regression manifest (tests/data/regression/regression.json) cut down
// to the entries a test names, with their images, in a folder of the test's: the tests of the
// regression set alter a copy, never the committed files.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/json_file.h"

namespace octtest {

inline const std::string kRegressionDir = OCT_SOURCE_DIR "/tests/data/regression";
inline const std::string kRegressionManifest = kRegressionDir + "/regression.json";

// The entry's name as the manifest spells it (its "name", or the scene's file name).
inline std::string entryName(const nlohmann::json& e) {
    if (e.contains("name")) return e["name"];
    std::string s = e["scene"];
    const size_t slash = s.rfind('/');
    if (slash != std::string::npos) s = s.substr(slash + 1);
    for (char& c : s) c = c == ':' ? '-' : c;
    return s;
}

// Writes `to`/regression.json listing the entries named `names` (all when empty), `edit`
// applied to the whole manifest, and copies their images; returns the manifest's path.
template <class Edit>
std::string copyRegression(const std::filesystem::path& to, const std::vector<std::string>& names,
                           Edit edit) {
    nlohmann::json m = readJson(kRegressionManifest);
    nlohmann::json kept = nlohmann::json::array();
    std::filesystem::create_directories(to);
    for (const nlohmann::json& e : m["scenes"]) {
        bool wanted = names.empty();
        for (const std::string& n : names) wanted = wanted || n == entryName(e);
        if (!wanted) continue;
        kept.push_back(e);
        for (const nlohmann::json& f : e["frames"])
            std::filesystem::copy_file(
                std::filesystem::path(kRegressionDir) / f["image"].get<std::string>(),
                to / f["image"].get<std::string>(),
                std::filesystem::copy_options::overwrite_existing);
    }
    m["scenes"] = kept;
    edit(m);
    const std::string path = (to / "regression.json").string();
    std::ofstream(path) << m.dump(2);
    return path;
}

inline std::string copyRegression(const std::filesystem::path& to,
                                  const std::vector<std::string>& names) {
    return copyRegression(to, names, [](nlohmann::json&) {});
}

}  // namespace octtest
