// How outputs are staged (core/io/output_file.h), in process: a temporary beside the output,
// created exclusively under a name nobody can guess, so a file, a symlink or a dangling
// symlink someone planted at a name octrace might use is never opened, never written, never
// created through; checkWritable leaves nothing behind.
#include "core/io/output_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

namespace oct {
namespace {

namespace fs = std::filesystem;

const std::string kNotOurs = "bytes that are not octrace's\n";

// The temporaries' suffixes a test hands out (setTempSuffixSourceForTests), in order; the last
// one repeats.
std::vector<std::string> gScriptedSuffixes;
size_t gNextSuffix = 0;

std::string scriptedSuffix() {
    const size_t i = std::min(gNextSuffix++, gScriptedSuffixes.size() - 1);
    return gScriptedSuffixes[i];
}

struct ScriptedSuffixes {
    explicit ScriptedSuffixes(std::vector<std::string> suffixes) {
        gScriptedSuffixes = std::move(suffixes);
        gNextSuffix = 0;
        setTempSuffixSourceForTests(scriptedSuffix);
    }
    ~ScriptedSuffixes() { setTempSuffixSourceForTests(nullptr); }
};

class OutputFiles : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        dir_ =
            fs::temp_directory_path() / ("octrace_output_file_test_" + std::to_string(::getpid()) +
                                         "_" + std::to_string(counter++));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    void put(const std::string& name, const std::string& bytes) const {
        std::ofstream(path(name), std::ios::binary) << bytes;
    }
    std::string read(const std::string& name) const {
        std::ifstream in(path(name), std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    std::set<std::string> listing() const {
        std::set<std::string> names;
        for (const auto& e : fs::directory_iterator(dir_)) names.insert(e.path().filename());
        return names;
    }
    // The name the temporaries had before: NAME.tmp.PID, with this process's pid.
    std::string oldTempName(const std::string& name) const {
        return name + ".tmp." + std::to_string(::getpid());
    }

    fs::path dir_;
};

// Item: NAME.tmp.PID was opened with fopen("wb"): a symlink there had its target truncated
// (by checkWritable) and then written; a regular file there was truncated; a dangling link's
// target was created. Each is planted at the name this process would have used.
TEST_F(OutputFiles, FilesAtTheOldTemporaryNamesAreNeverOpened) {
    put("victim.txt", kNotOurs);
    put(oldTempName("b.npy"), kNotOurs);
    fs::create_symlink(path("victim.txt"), path(oldTempName("a.png")));
    fs::create_symlink(path("made.txt"), path(oldTempName("c.json")));
    for (const char* out : {"a.png", "b.npy", "c.json"}) checkWritable(path(out));
    OutputSet set;
    for (const char* out : {"a.png", "b.npy", "c.json"})
        set.stage(path(out), std::string(out).data(), std::string(out).size());
    set.commit();

    EXPECT_EQ(read("victim.txt"), kNotOurs);
    EXPECT_EQ(read(oldTempName("b.npy")), kNotOurs);
    EXPECT_FALSE(fs::exists(path("made.txt"))) << "created through the dangling link";
    for (const char* out : {"a.png", "b.npy", "c.json"}) {
        EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path(out)))) << out;
        EXPECT_EQ(read(out), out);
    }
    EXPECT_TRUE(fs::is_symlink(path(oldTempName("a.png"))));
    EXPECT_TRUE(fs::is_symlink(path(oldTempName("c.json"))));
}

// checkWritable probes the folder by creating a file; the probe is gone afterwards and no
// existing output is touched.
TEST_F(OutputFiles, CheckWritableLeavesNothingBehind) {
    put("kept.png", kNotOurs);
    checkWritable(path("new.png"));
    checkWritable(path("kept.png"));
    EXPECT_EQ(listing(), std::set<std::string>{"kept.png"});
    EXPECT_EQ(read("kept.png"), kNotOurs);
    EXPECT_THROW(checkWritable(path("no-such-folder/x.png")), IoError);
}

// The temporary is created exclusively: the names drawn first are taken (a file, a symlink),
// neither is opened, and the third name is used.
TEST_F(OutputFiles, TemporaryIsCreatedExclusively) {
    put("victim.txt", kNotOurs);
    put("out.png.tmp.taken1", kNotOurs);
    fs::create_symlink(path("victim.txt"), path("out.png.tmp.taken2"));
    for (bool probe : {true, false}) {
        ScriptedSuffixes names({"taken1", "taken2", "free"});
        if (probe)
            checkWritable(path("out.png"));
        else
            writeFileAtomic(path("out.png"), "new", 3);
    }
    EXPECT_EQ(read("out.png"), "new");
    EXPECT_EQ(read("out.png.tmp.taken1"), kNotOurs);
    EXPECT_EQ(read("victim.txt"), kNotOurs);
    EXPECT_TRUE(fs::is_symlink(path("out.png.tmp.taken2")));
    EXPECT_EQ(listing(), (std::set<std::string>{"out.png", "out.png.tmp.taken1",
                                                "out.png.tmp.taken2", "victim.txt"}));
}

// When every name drawn is taken the write is an error naming the output; nothing is touched.
TEST_F(OutputFiles, NoFreeTemporaryNameIsAnErrorThatTouchesNothing) {
    put("out.png", kNotOurs);
    put("out.png.tmp.taken", kNotOurs);
    ScriptedSuffixes names({"taken"});
    try {
        writeFileAtomic(path("out.png"), "new", 3);
        ADD_FAILURE() << "wrote through a taken name";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(path("out.png") + ".tmp.*"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(checkWritable(path("out.png")), IoError);
    EXPECT_EQ(read("out.png"), kNotOurs);
    EXPECT_EQ(read("out.png.tmp.taken"), kNotOurs);
    EXPECT_EQ(listing(), (std::set<std::string>{"out.png", "out.png.tmp.taken"}));
}

// OutputLock: while one is held on a name a second is refused (flock conflicts between two
// opens of the file, in one process as between two); the lock file octrace made is removed
// when the lock ends, and the name can be locked again.
TEST_F(OutputFiles, LockOnANameIsHeldUntilItEnds) {
    {
        const OutputLock first(path("H"));
        EXPECT_EQ(listing(), std::set<std::string>{"H.lock"});
        try {
            const OutputLock second(path("H"));
            ADD_FAILURE() << "locked twice";
        } catch (const IoError& e) {
            EXPECT_NE(
                std::string(e.what()).find("another octrace run is writing '" + path("H") + "'"),
                std::string::npos)
                << e.what();
        }
    }
    EXPECT_EQ(listing(), std::set<std::string>{});
    const OutputLock again(path("H"));
}

// A file at NAME.lock that octrace did not make is locked and left as it was; one that holds
// the text octrace writes into its own (a killed run's) is removed; a symlink there is refused
// and its target left alone.
TEST_F(OutputFiles, LockFileThatIsNotOctracesIsLeftAlone) {
    put("H.lock", kNotOurs);
    { const OutputLock lock(path("H")); }
    EXPECT_EQ(read("H.lock"), kNotOurs);

    const std::string text = [&] {
        const OutputLock made(path("L"));
        return read("L.lock");
    }();
    put("M.lock", text);
    { const OutputLock stale(path("M")); }
    EXPECT_FALSE(fs::exists(path("M.lock"))) << "a killed run's lock file stays";

    put("victim.txt", kNotOurs);
    fs::create_symlink(path("victim.txt"), path("S.lock"));
    EXPECT_THROW(OutputLock(path("S")), IoError);
    EXPECT_EQ(read("victim.txt"), kNotOurs);
    EXPECT_TRUE(fs::is_symlink(path("S.lock")));
}

// lockOutputs: one lock per output; an output that is another's lock file is refused.
TEST_F(OutputFiles, LockOutputsLocksEachOutput) {
    {
        const std::vector<OutputLock> locks = lockOutputs({path("a.png"), "", "-", path("b.npy")});
        EXPECT_EQ(locks.size(), 2u);
        EXPECT_THROW(OutputLock(path("b.npy")), IoError);
    }
    EXPECT_EQ(listing(), std::set<std::string>{});
    EXPECT_THROW(lockOutputs({path("x"), path("x.lock")}), IoError);
    EXPECT_EQ(listing(), std::set<std::string>{});
}

}  // namespace
}  // namespace oct
