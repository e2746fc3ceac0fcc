// What a refusal for memory says (core/system/resources.h): the need and what is left, in short
// binary units, and estimates that saturate rather than wrap (a wrapped product would pass).
#include "core/system/resources.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

namespace oct {
namespace {

TEST(Resources, BytesAreShownInShortBinaryUnits) {
    EXPECT_EQ(bytesText(512), "512 bytes");
    EXPECT_EQ(bytesText(uint64_t(3) << 20), "3.00 MiB");
    EXPECT_EQ(bytesText(uint64_t(25) << 30), "25.0 GiB");
    EXPECT_EQ(bytesText(uint64_t(300) << 30), "300 GiB");
}

TEST(Resources, EstimatesSaturateInsteadOfWrapping) {
    const uint64_t most = std::numeric_limits<uint64_t>::max();
    EXPECT_EQ(saturatingMul(uint64_t(1) << 40, uint64_t(1) << 40), most);
    EXPECT_EQ(saturatingMul(0, most), 0u);
    EXPECT_EQ(saturatingMul(6, 7), 42u);
    EXPECT_EQ(saturatingAdd(most, 1), most);
    EXPECT_EQ(saturatingAdd(40, 2), 42u);
}

TEST(Resources, AShortfallNamesTheNeedTheLimitAndWhatToDo) {
    const MemoryLimit left{uint64_t(1) << 30, "left of the 4.00 GiB of physical memory"};
    EXPECT_EQ(memoryShortfall(uint64_t(1) << 30, "x", "y", left), "");  // exactly what is left
    const std::string why =
        memoryShortfall(uint64_t(3) << 30, "octrace rays --size 9x9", "use a smaller --size", left);
    EXPECT_EQ(why,
              "octrace rays --size 9x9 needs about 3.00 GiB of memory, more than the 1.00 GiB "
              "left of the 4.00 GiB of physical memory; use a smaller --size");
    // The machine's own limit: something is left, and an absurd need is refused.
    EXPECT_GT(memoryLimit().bytes, 0u);
    EXPECT_THROW(checkMemory(std::numeric_limits<uint64_t>::max(), "x", "y"), ResourceError);
    EXPECT_NO_THROW(checkMemory(1, "x", "y"));
    EXPECT_GE(onlineCores(), 1);
}

}  // namespace
}  // namespace oct
