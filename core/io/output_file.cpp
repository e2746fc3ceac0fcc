#include "core/io/output_file.h"

#include <stb_image_write.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace oct {

void writeFileAtomic(const std::string& path, const void* data, size_t bytes) {
    std::string tmp = path + ".tmp." + std::to_string(::getpid());
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
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        err = errno;
        std::remove(tmp.c_str());
        throw IoError("cannot replace '" + path + "': " + std::strerror(err));
    }
}

namespace {
void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    auto* p = static_cast<uint8_t*>(data);
    out->insert(out->end(), p, p + size);
}
}  // namespace

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    std::vector<uint8_t> png;
    if (!stbi_write_png_to_func(appendBytes, &png, width, height, 3, rgb.data(), width * 3))
        throw IoError("cannot encode the PNG for '" + path + "'");
    writeFileAtomic(path, png);
}

}  // namespace oct
