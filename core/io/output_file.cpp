#include "core/io/output_file.h"

#include <stb_image_write.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace oct {

namespace {

std::string tempNameFor(const std::string& path) {
    return path + ".tmp." + std::to_string(::getpid());
}

// Writes bytes to tmp; on failure removes it and throws naming the target path.
void writeTemp(const std::string& path, const std::string& tmp, const void* data, size_t bytes) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f)
        throw IoError("cannot write '" + path + "': " + std::strerror(errno) +
                      " (check that the folder exists and is writable)");
    bool ok = bytes == 0 || std::fwrite(data, 1, bytes, f) == bytes;
    int err = errno;
    ok = (std::fclose(f) == 0) && ok;
    if (!ok) {
        std::remove(tmp.c_str());
        throw IoError("cannot write '" + path + "': " + std::strerror(err ? err : EIO));
    }
}

void renameInto(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int err = errno;
        std::remove(tmp.c_str());
        throw IoError("cannot replace '" + path + "': " + std::strerror(err));
    }
}

}  // namespace

void writeFileAtomic(const std::string& path, const void* data, size_t bytes) {
    std::string tmp = tempNameFor(path);
    writeTemp(path, tmp, data, bytes);
    renameInto(tmp, path);
}

OutputSet::~OutputSet() {
    for (const Staged& s : staged_) std::remove(s.tmp.c_str());
}

void OutputSet::stage(const std::string& path, const void* data, size_t bytes) {
    std::string tmp = tempNameFor(path);
    writeTemp(path, tmp, data, bytes);
    staged_.push_back({path, tmp});
}

void OutputSet::commit() {
    // Renames cannot fail for lack of space; what can fail (a vanished folder) is reported, and
    // the temporaries not yet renamed are removed by the destructor.
    while (!staged_.empty()) {
        Staged s = staged_.front();
        staged_.erase(staged_.begin());
        renameInto(s.tmp, s.path);
    }
}

void checkWritable(const std::string& path) {
    std::string tmp = tempNameFor(path);
    writeTemp(path, tmp, "", 0);
    std::remove(tmp.c_str());
}

namespace {

void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    auto* p = static_cast<uint8_t*>(data);
    out->insert(out->end(), p, p + size);
}
}  // namespace

std::vector<uint8_t> encodePng(const std::string& path, int width, int height,
                               const std::vector<uint8_t>& rgb) {
    std::vector<uint8_t> png;
    if (!stbi_write_png_to_func(appendBytes, &png, width, height, 3, rgb.data(), width * 3))
        throw IoError("cannot encode the PNG for '" + path + "'");
    return png;
}

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    writeFileAtomic(path, encodePng(path, width, height, rgb));
}

}  // namespace oct
