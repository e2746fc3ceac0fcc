// Every numeric option of every command goes through the one validator (apps/cli.h, numberIn and
// finiteNumber): the commands are walked as CLI11 registered them, so a new numeric option
// cannot ship without it. NaN and infinities are refused with one line naming the option and
// exit status 2 (kExitError); so is a value outside the option's range, its bounds printed short.
// And the out-of-memory advice of each command names only options it has.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace oct
