// The scene loader's small helpers (loader_detail.h).
#include "core/scene/loader_detail.h"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace oct::scene_detail {

namespace fs = std::filesystem;

std::string inQuotes(const std::string& s) { return "'" + s + "'"; }

std::string toLower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string lowerExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    return toLower(ext.empty() ? ext : ext.substr(1));
}

std::string joinList(const std::vector<std::string>& items, const std::string& lastJoin) {
    std::string out;
    for (size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += i + 1 == items.size() ? lastJoin : ", ";
        out += items[i];
    }
    return out;
}

void trimLine(std::string& s) {
    size_t begin = s.find_first_not_of(" \t\r\n");
    size_t end = s.find_last_not_of(" \t\r\n");
    s = begin == std::string::npos ? std::string() : s.substr(begin, end - begin + 1);
}

std::ifstream openOrThrow(const std::string& path, std::ios::openmode mode) {
    std::ifstream in(path, mode);
    if (!in) {
        const int error = errno;
        throw SceneError("cannot open " + inQuotes(path) + ": " + std::strerror(error), error);
    }
    return in;
}

uint64_t fileSize(const std::string& path) {
    std::error_code ec;
    uint64_t size = fs::file_size(path, ec);
    if (ec) throw SceneError("cannot read " + inQuotes(path) + ": " + ec.message(), ec.value());
    return size;
}

size_t stripUtf8Bom(std::string& firstLine) {
    if (firstLine.compare(0, 3, kUtf8Bom) != 0) return 0;
    firstLine.erase(0, 3);
    return 3;
}

}  // namespace oct::scene_detail
