// The manifest of the malformed-scene corpus (tests/data/bad/manifest.txt), read the same way by
// the library test (tests/core/bad_input_test.cpp) and the CLI test
// (tests/apps/bad_input_cli_test.cpp). One line per file: "FILE error:TEXT" (loading must fail
// with a message containing TEXT) or "FILE ok:key=n,key=n" (loading must succeed and report
// exactly these drops: invalid_index, non_finite, degenerate, too_few_vertices).
#pragma once

#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace octtest {

const std::string kBadDir = std::string(OCT_SOURCE_DIR) + "/tests/data/bad";

struct BadFile {
    std::string file;
    bool expectError = false;
    std::string errorText;
    std::map<std::string, uint64_t> drops;

    uint64_t totalDropped() const {
        uint64_t n = 0;
        for (const auto& [key, count] : drops) n += count;
        return n;
    }
};

// A line that is neither form becomes an expected error that no message matches, so the tests
// fail on it instead of skipping it.
inline std::vector<BadFile> readBadManifest() {
    std::vector<BadFile> entries;
    std::ifstream in(kBadDir + "/manifest.txt");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const size_t space = line.find(' ');
        BadFile e;
        e.file = line.substr(0, space);
        const std::string expect = space == std::string::npos ? "" : line.substr(space + 1);
        if (expect.rfind("error:", 0) == 0) {
            e.expectError = true;
            e.errorText = expect.substr(6);
        } else if (expect.rfind("ok:", 0) == 0) {
            std::istringstream counts(expect.substr(3));
            std::string item;
            while (std::getline(counts, item, ',')) {
                const size_t eq = item.find('=');
                e.drops[item.substr(0, eq)] = std::stoull(item.substr(eq + 1));
            }
        } else {
            e.errorText = "<bad manifest line: " + line + ">";
            e.expectError = true;
        }
        entries.push_back(e);
    }
    return entries;
}

}  // namespace octtest
