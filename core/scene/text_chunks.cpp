// Whole-file reads and line-aligned chunks for the fast text readers (text_chunks.h).
#include "core/scene/text_chunks.h"

#include <omp.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <new>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {

FileText::FileText(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    const uint64_t size = fileSize(path);
    bytes_ = makeHugeArray<char>(size_t(size));
    in.read(bytes_.get(), std::streamsize(size));  // not zeroed first: every byte is read over
    size_ = size_t(in.gcount());                   // a file that shrank meanwhile: what was there
}

std::vector<std::pair<size_t, size_t>> lineAlignedChunks(std::string_view text, size_t from) {
    std::vector<std::pair<size_t, size_t>> chunks;
    const size_t size = text.size() > from ? text.size() - from : 0;
    const size_t pieces = std::min(size_t(4 * std::max(1, omp_get_max_threads())), size / 4096 + 1);
    size_t begin = from;
    for (size_t k = 1; k <= pieces && begin < text.size(); ++k) {
        size_t end = k == pieces ? text.size() : std::max(begin, from + size / pieces * k);
        if (end < text.size()) {
            const void* eol = std::memchr(text.data() + end, '\n', text.size() - end);
            end = eol ? size_t(static_cast<const char*>(eol) - text.data()) + 1 : text.size();
        }
        chunks.push_back({begin, end});
        begin = end;
    }
    return chunks;
}

}  // namespace oct::scene_detail
