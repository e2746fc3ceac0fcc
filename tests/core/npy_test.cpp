// readNpy on headers written by hand: numpy reads the header dict with Python's literal parser
// (numpy.lib.format, ast.literal_eval), so keys and strings may use either quote and any
// spacing; readNpy must read what numpy reads, and refuse what it refuses.
#include "core/io/npy.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "core/io/ray_file.h"

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

// trace builds its output files in place (NpyBuffer): the same bytes as encodeNpy.
TEST_F(NpyFiles, BufferFilledInPlaceEqualsEncodedFile) {
    const float values[5] = {1.5f, -0.0f, INFINITY, 3.25f, 7.0f};
    NpyBuffer b("<f4", {5}, 4);
    std::memcpy(b.data(), values, sizeof values);
    EXPECT_EQ((reinterpret_cast<uintptr_t>(b.data()) - reinterpret_cast<uintptr_t>(b.bytes())) % 64,
              0u);
    const std::vector<uint8_t> want = encodeNpy("<f4", {5}, values, 4);
    ASSERT_EQ(b.size(), want.size());
    EXPECT_EQ(std::memcmp(b.bytes(), want.data(), want.size()), 0);
    EXPECT_THROW(NpyBuffer("<f4", {5}, 8), IoError);
}

// Large arrays are written from the caller's buffer behind a separate header (stageNpy, and
// writeNpy through it): the file holds the same bytes as encodeNpy's copy.
TEST_F(NpyFiles, StagedFromTheCallersBufferEqualsEncodedFile) {
    const int32_t values[6] = {-1, 0, 7, 1 << 30, -5, 42};
    const std::string staged = (dir_ / "staged.npy").string();
    OutputSet out;
    stageNpy(out, staged, "<i4", {3, 2}, values, 4);
    out.commit();
    const std::vector<uint8_t> want = encodeNpy("<i4", {3, 2}, values, 4);
    std::ifstream in(staged, std::ios::binary);
    const std::string got{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    ASSERT_EQ(got.size(), want.size());
    EXPECT_EQ(std::memcmp(got.data(), want.data(), want.size()), 0);
    writeNpy((dir_ / "written.npy").string(), "<i4", {3, 2}, values, 4);
    const NpyArray back = readNpy((dir_ / "written.npy").string());
    EXPECT_EQ(back.shape, (std::vector<uint64_t>{3, 2}));
    EXPECT_EQ(std::memcmp(back.data.data(), values, sizeof values), 0);
    OutputSet wrong;
    EXPECT_THROW(stageNpy(wrong, (dir_ / "wrong.npy").string(), "<i4", {3, 2}, values, 8), IoError);
}

// Rows are checked in parallel; the error names the lowest bad row, as a sequential scan would.
TEST_F(NpyFiles, RayFileErrorNamesTheLowestBadRow) {
    const uint64_t rows = 200000;
    std::vector<float> r(rows * 8);
    for (uint64_t i = 0; i < rows; ++i) {
        r[8 * i + 3] = 1.0f;  // direction +x, tmin 0, tmax +inf
        r[8 * i + 7] = INFINITY;
    }
    r[8 * 150001 + 6] = -1.0f;  // negative tmin
    r[8 * 70003 + 4] = NAN;     // NaN direction
    r[8 * 190000 + 0] = INFINITY;
    const std::vector<uint8_t> bytes = encodeNpy("<f4", {rows, 8}, r.data(), 4);
    const std::string path = write("rays.npy", std::string(bytes.begin(), bytes.end()));
    try {
        readRayFile(path);
        FAIL() << "bad rows accepted";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("row 70003:"), std::string::npos) << e.what();
    }
    r[8 * 70003 + 4] = 0.0f;
    r[8 * 150001 + 6] = 0.0f;
    r[8 * 190000 + 0] = 0.0f;
    const std::vector<uint8_t> good = encodeNpy("<f4", {rows, 8}, r.data(), 4);
    const std::string okPath = write("ok.npy", std::string(good.begin(), good.end()));
    std::unique_ptr<float[]> into;
    EXPECT_EQ(readRayFileInto(okPath,
                              [&into](uint64_t n) {
                                  into.reset(new float[n * 8]);
                                  return into.get();
                              }),
              rows);
    EXPECT_EQ(std::memcmp(into.get(), r.data(), rows * 32), 0);
}

}  // namespace
}  // namespace oct
