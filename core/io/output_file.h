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

// Several outputs of one command, all or none: stage() writes each to a temporary name,
// commit() renames them all into place once every one was written. Destroying an uncommitted
// set removes its temporaries, so a failure anywhere leaves every target as it was.
class OutputSet {
public:
    OutputSet() = default;
    ~OutputSet();
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;

    void stage(const std::string& path, const void* data, size_t bytes);
    void stage(const std::string& path, const std::vector<uint8_t>& bytes) {
        stage(path, bytes.data(), bytes.size());
    }
    void commit();

private:
    struct Staged {
        std::string path, tmp;
    };
    std::vector<Staged> staged_;
};

// Fails early, before heavy work, when a file cannot be created in path's folder.
void checkWritable(const std::string& path);
inline void writeFileAtomic(const std::string& path, const std::vector<uint8_t>& bytes) {
    writeFileAtomic(path, bytes.data(), bytes.size());
}

// Encodes an 8-bit RGB image as PNG (stb_image_write, Debian's libstb) and writes it atomically.
void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);
std::vector<uint8_t> encodePng(const std::string& path, int width, int height,
                               const std::vector<uint8_t>& rgb);

}  // namespace oct
