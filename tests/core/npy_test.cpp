// readNpy on headers written by hand: numpy reads the header dict with Python's literal parser
// (numpy.lib.format, ast.literal_eval), so keys and strings may use either quote and any
// spacing; readNpy must read what numpy reads, and refuse what it refuses.
#include "core/io/npy.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace oct {
namespace {

namespace fs = std::filesystem;

// A version 1.0 file with the given header dict and 6 little-endian floats 0..5.
std::string npyBytes(std::string dict) {
    const size_t total = 10 + dict.size() + 1;
    dict.append((64 - total % 64) % 64, ' ');
    dict.push_back('\n');
    std::string bytes("\x93NUMPY\x01\x00", 8);
    bytes.push_back(char(dict.size() & 0xff));
    bytes.push_back(char(dict.size() >> 8));
    bytes += dict;
    for (int i = 0; i < 6; ++i) {
        const float v = float(i);
        bytes.append(reinterpret_cast<const char*>(&v), 4);
    }
    return bytes;
}

class NpyFiles : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        dir_ = fs::temp_directory_path() /
               ("octrace_npy_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string write(const std::string& name, const std::string& bytes) {
        const std::string p = (dir_ / name).string();
        std::ofstream(p, std::ios::binary) << bytes;
        return p;
    }
    fs::path dir_;
};

void expectTwoByThreeFloats(const NpyArray& a) {
    EXPECT_EQ(a.descr, "<f4");
    EXPECT_EQ(a.shape, (std::vector<uint64_t>{2, 3}));
    ASSERT_EQ(a.data.size(), 24u);
    float last;
    std::memcpy(&last, a.data.data() + 20, 4);
    EXPECT_EQ(last, 5.0f);
}

TEST_F(NpyFiles, ReadsSingleAndDoubleQuotedHeaders) {
    for (const char* dict : {"{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
                             "{\"descr\": \"<f4\", \"fortran_order\": False, \"shape\": (2, 3)}",
                             "{\"descr\":\"<f4\",'fortran_order':False,\"shape\":(2,3)}"}) {
        SCOPED_TRACE(dict);
        try {
            expectTwoByThreeFloats(readNpy(write("a.npy", npyBytes(dict))));
        } catch (const IoError& e) {
            ADD_FAILURE() << e.what();
        }
    }
}

TEST_F(NpyFiles, RefusesMismatchedQuotesAndFortranOrder) {
    EXPECT_THROW(readNpy(write("a.npy", npyBytes("{\"descr': '<f4', 'fortran_order': False, "
                                                 "'shape': (2, 3), }"))),
                 IoError);
    EXPECT_THROW(readNpy(write("b.npy", npyBytes("{\"descr\": \"<f4\", \"fortran_order\": True, "
                                                 "\"shape\": (2, 3)}"))),
                 IoError);
}

}  // namespace
}  // namespace oct
