// Every numeric option of every command goes through the one validator (apps/cli.h, numberIn and
// finiteNumber): the commands are walked as CLI11 registered them, so a new numeric option
// cannot ship without it. NaN and infinities are refused with one line naming the option and
// exit status 2 (kExitError); so is a value outside the option's range, its bounds printed short.
// And the out-of-memory advice of each command names only options it has.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>

#include "apps/cli.h"
#include "tests/cli_harness.h"

namespace oct {
namespace {

using octtest::RunResult;

bool isNumeric(const CLI::Option* o) {
    const std::string type = o->get_type_name();
    for (const char* t : {"INT", "UINT", "FLOAT", "NUMBER"})
        if (type == t || type.rfind(std::string(t) + ":", 0) == 0) return true;
    return false;
}

struct Command {
    std::string name;
    std::vector<std::string> base;  // the command and its required arguments
    std::vector<std::string> numeric;
};

// Every subcommand with placeholders for what it requires (the scene grid:10, a file name for
// the rest), and its numeric options.
std::vector<Command> commands(const std::string& dir) {
    CLI::App app;
    registerCommands(app);
    std::vector<Command> out;
    for (CLI::App* sub : app.get_subcommands({})) {
        Command c;
        c.name = sub->get_name();
        c.base = {c.name};
        for (CLI::Option* o : sub->get_options()) {
            if (o->get_required()) {
                if (o->get_positional()) {
                    c.base.push_back("grid:10");
                } else {
                    c.base.push_back(o->get_name());
                    c.base.push_back(dir + "/placeholder" + o->get_name() + ".npy");
                }
            }
            if (isNumeric(o)) c.numeric.push_back(o->get_name());
        }
        out.push_back(c);
    }
    return out;
}

TEST(NumericOptions, EveryOneHasTheValidator) {
    CLI::App app;
    registerCommands(app);
    size_t seen = 0;
    for (CLI::App* sub : app.get_subcommands({}))
        for (CLI::Option* o : sub->get_options()) {
            if (!isNumeric(o)) continue;
            ++seen;
            EXPECT_NO_THROW(o->get_validator(kNumberValidator))
                << "octrace " << sub->get_name() << " " << o->get_name()
                << ": check(numberIn(lo, hi)) or check(finiteNumber()) (apps/cli.h)";
        }
    EXPECT_GT(seen, 30u);  // the walk found the options
}

TEST(NumericOptions, NanAndInfinitiesAreRefusedWithOneLine) {
    octtest::TempDir dir("numeric_options");
    octtest::RunOptions opt;
    opt.timeoutSeconds = 20;
    opt.workingDir = dir.path().string();  // an option let through must not write here
    for (const Command& c : commands(dir.path().string()))
        for (const std::string& name : c.numeric)
            for (const char* value : {"nan", "inf", "-inf", "-NaN", "Infinity"}) {
                std::vector<std::string> args = c.base;
                args.push_back(name + "=" + value);  // = so that "-inf" is not an option
                const RunResult r = octtest::runOctrace(args, dir.path() / "capture", opt);
                SCOPED_TRACE("octrace " + c.name + " " + name + "=" + value);
                EXPECT_TRUE(octtest::isOneLineError(r));
                EXPECT_EQ(r.status, kExitError) << octtest::show(r);
                EXPECT_NE(r.err.find(name + ": " + value + " is not a finite number"),
                          std::string::npos)
                    << r.err;
            }
}

TEST(NumericOptions, OutOfRangeIsOneShortLine) {
    octtest::TempDir dir("numeric_range");
    octtest::RunOptions opt;
    opt.timeoutSeconds = 20;
    opt.workingDir = dir.path().string();
    // bench --max-seconds 0 printed the double's largest value in full, 309 digits.
    const std::vector<std::vector<std::string>> cases = {
        {"bench", "--max-seconds", "0"},
        {"bench", "--max-seconds", "1e-300"},
        {"bench", "--max-seconds", "-1"},
        {"bench", "--max-seconds", "1e999"},
        {"certify", "grid:10", "--rays", "R.npy", "--hits", "H", "--edge-tolerance", "2"},
        {"render", "grid:10", "--out", "o.png", "--max-prims", "0"},
        {"rays", "grid:10", "--out", "R.npy", "--count", "100000001"},
    };
    for (const std::vector<std::string>& args : cases) {
        const RunResult r = octtest::runOctrace(args, dir.path() / "capture", opt);
        SCOPED_TRACE(args[0] + " " + args[args.size() - 2] + " " + args.back());
        EXPECT_TRUE(octtest::isOneLineError(r));
        EXPECT_EQ(r.status, kExitError) << octtest::show(r);
        EXPECT_NE(r.err.find(args[args.size() - 2] + ": " + args.back()), std::string::npos)
            << r.err;
        EXPECT_LT(r.err.size(), 160u) << r.err;
    }
}

TEST(NumericOptions, OutOfMemoryAdviceNamesOnlyTheCommandsOptions) {
    CLI::App app;
    registerCommands(app);
    const std::regex option("--[a-z-]+");
    for (CLI::App* sub : app.get_subcommands({})) {
        const std::string advice = outOfMemoryAdvice(*sub);
        SCOPED_TRACE(advice);
        EXPECT_NE(advice.find("octrace " + sub->get_name()), std::string::npos);
        for (std::sregex_iterator m(advice.begin(), advice.end(), option), end; m != end; ++m)
            EXPECT_NE(sub->get_option_no_throw(m->str()), nullptr)
                << "octrace " << sub->get_name() << " has no " << m->str();
    }
    // The commands without an octree option get no octree advice.
    const std::string certify = outOfMemoryAdvice(*app.get_subcommand("certify"));
    EXPECT_EQ(certify.find("--max-depth"), std::string::npos) << certify;
    EXPECT_NE(certify.find("--rays"), std::string::npos) << certify;
}

// What each command is given beside the option under test, so that an accepted value runs a
// small job (a tiny image, few rays) and only the value can make it large. {} is the folder.
std::vector<std::string> smallJob(const std::string& command, const std::string& dir) {
    const std::map<std::string, std::vector<std::string>> jobs = {
        {"info", {"info", "grid:10"}},
        {"render", {"render", "grid:10", "--size", "8x8", "--out", dir + "/o.png"}},
        {"trace", {"trace", "grid:10", "--rays", dir + "/R.npy", "--out", dir + "/T"}},
        {"validate",
         {"validate", "grid:10", "--size", "8x8", "--rays", "100", "--box-rays", "100"}},
        {"bench",
         {"bench", "--quick", "--clouds", "1k", "--meshes", "none", "--accel", "linear",
          "--backend", "cpu", "--size", "8x8", "--repeats", "1", "--warmup", "0", "--out",
          dir + "/bench", "--no-progress"}},
        {"rays", {"rays", "grid:10", "--count", "10", "--size", "2x2", "--out", dir + "/R2.npy"}},
        {"certify", {"certify", "grid:10", "--rays", dir + "/R.npy", "--hits", dir + "/H"}},
        {"explain", {"explain", "grid:10"}},
    };
    const auto it = jobs.find(command);
    return it == jobs.end() ? std::vector<std::string>{command} : it->second;
}

// The job without `option` and its value (the option under test replaces it).
std::vector<std::string> without(std::vector<std::string> args, const std::string& option) {
    for (size_t i = 0; i + 1 < args.size(); ++i)
        if (args[i] == option) {
            args.erase(args.begin() + long(i), args.begin() + long(i) + 2);
            break;
        }
    return args;
}

// 0, a negative and huge values for every numeric option of every command: each is refused with
// one line (exit 2) or runs to its end in bounded time (a verdict, 0, 1 or 3), never a hang, a
// signal or a library's message. `validate --box-rays 99999999999` ran for about 12 days.
TEST(NumericOptions, ZeroNegativeAndHugeAreRefusedOrRunBounded) {
    octtest::TempDir dir("numeric_bounds");
    const std::string d = dir.path().string();
    octtest::RunOptions opt;
    opt.timeoutSeconds = 60;
    opt.workingDir = d;
    ASSERT_EQ(octtest::runOctrace(
                  {"rays", "grid:10", "--count", "20", "--size", "2x2", "--out", d + "/R.npy"},
                  dir.path() / "capture", opt)
                  .status,
              0);
    ASSERT_EQ(octtest::runOctrace({"trace", "grid:10", "--rays", d + "/R.npy", "--out", d + "/H"},
                                  dir.path() / "capture", opt)
                  .status,
              0);
    for (const Command& c : commands(d))
        for (const std::string& name : c.numeric)
            for (const char* value : {"0", "-1", "99999999999", "1e300"}) {
                std::vector<std::string> args = without(smallJob(c.name, d), name);
                args.push_back(name + "=" + value);
                SCOPED_TRACE("octrace " + c.name + " " + name + "=" + value);
                const RunResult r = octtest::runOctrace(args, dir.path() / "capture", opt);
                ASSERT_FALSE(r.timedOut) << octtest::show(r);
                EXPECT_EQ(r.signal, 0) << octtest::show(r);
                if (r.status == kExitError) {
                    EXPECT_TRUE(octtest::isOneLineError(r));
                } else {
                    EXPECT_TRUE(r.status == 0 || r.status == 1 || r.status == 3)
                        << octtest::show(r);
                }
                for (const char* leak : {"terminate", "what()", "Thread creation", "bad_alloc"})
                    EXPECT_EQ(r.err.find(leak), std::string::npos) << octtest::show(r);
            }
}

}  // namespace
}  // namespace oct
