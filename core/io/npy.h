// NumPy .npy files, format version 1.0 (numpy.lib.format): the 6-byte magic "\x93NUMPY", version
// bytes 1 0, a little-endian uint16 header length, then an ASCII Python dict
// {'descr': '<f4', 'fortran_order': False, 'shape': (H, W), } padded with spaces and a final
// '\n' so that the data starts at a multiple of 64 bytes; then the raw C-order data.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/io/output_file.h"
#include "core/system/resources.h"

namespace oct {

struct NpyArray {
    std::string descr;  // "<f4", "<i4", "<u4", "|u1"
    std::vector<uint64_t> shape;
    std::vector<uint8_t> data;  // C order, little-endian

    uint64_t elementCount() const;
};

// A .npy file built in place: the preamble and header written, the data section left for the
// caller to fill (trace writes its hits straight into it: no zero-filled array, no copy). The
// data starts at a multiple of 64 bytes from the start of the buffer, so it is aligned for any
// element type.
class NpyBuffer {
public:
    NpyBuffer(const std::string& descr, const std::vector<uint64_t>& shape, size_t elementSize);
    void* data() { return bytes_.get() + dataOffset_; }
    const uint8_t* bytes() const { return bytes_.get(); }
    size_t size() const { return size_; }

private:
    HugeArray<uint8_t> bytes_;  // not value-initialised; on huge pages (resources.h)
    size_t size_ = 0, dataOffset_ = 0;
};

// The complete file's bytes. descr and the element size must match.
std::vector<uint8_t> encodeNpy(const std::string& descr, const std::vector<uint64_t>& shape,
                               const void* data, size_t elementSize);

// Stages the file in `out` from the caller's data as it lies: the preamble and header, then
// `data` itself (no encoded copy: a ray file of 8.6 GB needs no second 8.6 GB). `data` must
// stay alive until the file is staged (stage writes it at once).
void stageNpy(OutputSet& out, const std::string& path, const std::string& descr,
              const std::vector<uint64_t>& shape, const void* data, size_t elementSize);

// Writes atomically (output_file.h), streamed as stageNpy.
void writeNpy(const std::string& path, const std::string& descr, const std::vector<uint64_t>& shape,
              const void* data, size_t elementSize);

// The preamble and header dict of a version 1.x, 2.x or 3.x .npy file open in `in`, read and
// checked (magic, version, a header inside the file, a dict with descr, fortran_order False
// and a shape of decimal entries); `in` is left at the data, which start at dataStart. Throws
// IoError "'PATH' is not a valid .npy file: ..." naming what is wrong. The one header reader:
// readNpy and the ray file reader (ray_file.h) both start here.
struct NpyHeader {
    std::string descr;
    std::vector<uint64_t> shape;
    uint64_t dataStart = 0;
};
class InputFile;
NpyHeader readNpyHeader(InputFile& in, const std::string& path);

// A shape as Python writes it: "(3, 8)", "(5,)".
std::string npyShapeText(const std::vector<uint64_t>& shape);

// Reads a version 1.x, 2.x or 3.x .npy file. Throws IoError naming the file and the problem for
// a missing file or one that is not a regular file (refused unread, core/io/input_file.h;
// `what` names it there: "hits"), a bad magic or header, Fortran order, or a data size that
// disagrees with the shape (checked before allocating, overflow-safe). `check`, when given,
// sees the dtype and shape (no data yet) before the data are read and may throw: a file of
// the wrong shape is then refused without reading its data.
NpyArray readNpy(const std::string& path, const std::string& what = "the .npy file",
                 const std::function<void(const NpyArray&)>& check = {});

}  // namespace oct
