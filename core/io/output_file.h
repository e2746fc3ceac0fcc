// Output files are written to a temporary name beside the target and renamed into place only
// when complete, so a failure never leaves a partial file and an existing file is replaced
// only by a complete one (rename within one directory is atomic on POSIX).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace oct {

class IoError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

void writeFileAtomic(const std::string& path, const void* data, size_t bytes);
inline void writeFileAtomic(const std::string& path, const std::vector<uint8_t>& bytes) {
    writeFileAtomic(path, bytes.data(), bytes.size());
}

// Encodes an 8-bit RGB image as PNG (stb_image_write, Debian's libstb) and writes it atomically.
void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace oct
