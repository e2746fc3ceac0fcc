// The explain page in a real browser: headless Chromium (Debian's chromium, installed by
// scripts/setup) opens the file octrace wrote, from file:// with no network, with software WebGL
// (SwiftShader). One run dumps the DOM after the page's script ran and takes a screenshot:
// the page must say it rendered, list every step, report no script error, and the screenshot
// must show a picture with the primary ray's magenta in it. Skips only without a Chromium.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "tests/teach/page_data.h"

namespace oct {
namespace {

using namespace octtest;

using octtest::kMeshes;

// OCT_CHROMIUM, else the first of Debian's and other distributions' names on PATH.
std::string findChromium() {
    if (const char* env = std::getenv("OCT_CHROMIUM")) return env;
    const char* path = std::getenv("PATH");
    if (!path) return "";
    for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
        std::string dirs = path;
        size_t pos = 0;
        while (pos <= dirs.size()) {
            size_t end = dirs.find(':', pos);
            if (end == std::string::npos) end = dirs.size();
            const fs::path candidate = fs::path(dirs.substr(pos, end - pos)) / name;
            if (!candidate.empty() && ::access(candidate.c_str(), X_OK) == 0)
                return candidate.string();
            pos = end + 1;
        }
    }
    return "";
}

size_t count(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + what.size())) ++n;
    return n;
}

using octtest::dataOf;

struct Chromium {
    bool ok = false;
    std::string dom, log;
    double seconds = 0;
};

// Opens `url` in headless Chromium from file:// with no network and software WebGL and returns
// the DOM after its scripts ran (and a screenshot). The page kernel compiles synchronously
// (emcc -sWASM_ASYNC_COMPILATION=0), so everything the page does happens before its load
// event, which --dump-dom waits for; the page's clocks are real (a virtual time budget would
// freeze performance.now, and the click times with it).
Chromium runChromium(const std::string& chromium, const TempDir& dir, const std::string& url,
                     const std::string& shot) {
    const std::string dom = dir.str("dom.html"), log = dir.str("chromium.log");
    const std::vector<std::string> args = {
        chromium, "--headless", "--no-sandbox", "--disable-dev-shm-usage",
        // WebGL without a GPU: SwiftShader, Chromium's software GL.
        "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
        // No network, no first-run work, a fresh profile.
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run", "--disable-default-apps", "--user-data-dir=" + dir.str("profile"),
        "--enable-logging=stderr", "--v=0", "--hide-scrollbars", "--window-size=1400,900",
        "--screenshot=" + shot, "--dump-dom", url};
    std::string cmd = "timeout 120 ";
    for (const std::string& a : args) cmd += quote(a) + " ";
    cmd += ">" + quote(dom) + " 2>" + quote(log);
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(cmd.c_str());
    Chromium r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    r.dom = readFile(dom);
    r.log = readFile(log) + (r.ok ? "" : "\n(status " + std::to_string(status) + ")");
    return r;
}

TEST(ExplainPageInChromium, RendersTheSceneAndTheStepsWithoutErrors) {
    const std::string chromium = findChromium();
    if (chromium.empty())
        GTEST_SKIP() << "no chromium on PATH (scripts/setup installs Debian's chromium)";
    TempDir dir("browser");
    const std::string page = dir.str("page.html");
    RunResult r = runOctrace({"explain", kMeshes + "/teapot.obj", "--size", "64x64", "--pixel",
                              "30,34", "--accel", "hash", "--html", page},
                             dir.path());
    if (r.status != 0 && r.err.find("without the page's viewer") != std::string::npos)
        GTEST_SKIP() << "octrace built with -DOCT_VIEWER=OFF";
    ASSERT_EQ(r.status, 0) << show(r);
    const nlohmann::json data = nlohmann::json::parse(dataOf(readFile(page)));
    size_t steps = 0;
    for (const auto& l : data["lines"]) steps += !l.contains("heading");
    ASSERT_GT(steps, 10u);

    const std::string shot = dir.str("shot.png");
    const Chromium run = runChromium(chromium, dir, "file://" + page, shot);
    const std::string &domText = run.dom, &logText = run.log;
    RecordProperty("chromium_seconds", std::to_string(run.seconds));
    std::printf("chromium took %.2f s\n", run.seconds);
    ASSERT_TRUE(run.ok) << "chromium failed\n" << logText;

    // The page's own report (its first script catches errors and console.error calls).
    EXPECT_NE(domText.find("data-octrace=\"rendered\""), std::string::npos)
        << domText.substr(0, 3000) << "\n--- log ---\n"
        << logText;
    EXPECT_NE(domText.find("<pre id=\"octrace-errors\"></pre>"), std::string::npos)
        << "the page reported errors:\n"
        << domText.substr(domText.find("octrace-errors"), 2000);
    EXPECT_EQ(logText.find("Uncaught"), std::string::npos) << logText;
    EXPECT_EQ(count(domText, "<li class=\"step"), steps) << "the step list is incomplete";
    // With the kernel the page traces itself; without (a build without emscripten) it says
    // that it shows the recorded pixel only, and why.
    if (data["kernel"].is_null()) {
        EXPECT_NE(domText.find("data-kernel=\"absent\""), std::string::npos);
        EXPECT_NE(domText.find("This page shows the pixel octrace recorded, and cannot explain "
                               "others: this octrace was built without emscripten"),
                  std::string::npos);
    } else {
        EXPECT_NE(domText.find("data-kernel=\"ready\""), std::string::npos);
        EXPECT_NE(domText.find("This page traces rays itself"), std::string::npos);
    }
    EXPECT_NE(domText.find("<canvas"), std::string::npos) << "no WebGL canvas";

    // The screenshot: a picture (many colours), the primary ray's magenta in it.
    int w = 0, h = 0, channels = 0;
    stbi_uc* px = stbi_load(shot.c_str(), &w, &h, &channels, 3);
    ASSERT_NE(px, nullptr) << "no screenshot\n" << logText;
    EXPECT_EQ(w, 1400);
    EXPECT_EQ(h, 900);
    std::set<uint32_t> colours;
    size_t magenta = 0;
    for (int i = 0; i < w * h; ++i) {
        const stbi_uc* p = px + 3 * i;
        colours.insert(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
        magenta += p[0] > 200 && p[1] < 90 && p[2] > 200;
    }
    stbi_image_free(px);
    EXPECT_GT(colours.size(), 200u) << "the screenshot looks blank";
    EXPECT_GT(magenta, 30u) << "the ray (magenta) is not in the screenshot";
}

// The element's text as --dump-dom writes it (it escapes &, < and > in text).
std::string unescapeText(std::string s) {
    for (auto [from, to] : {std::pair<const char*, const char*>{"&lt;", "<"},
                            {"&gt;", ">"},
                            {"&quot;", "\""},
                            {"&amp;", "&"}}) {
        for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + 1))
            s.replace(p, std::strlen(from), to);
    }
    return s;
}

// The page traces pixels itself: for each of a few layouts (and a point cloud) it explains
// pixels it was not written for, in Chromium, with octrace's kernel compiled to WebAssembly;
// each explanation must be byte for byte what `octrace explain --json --pixel X,Y` prints.
TEST(ExplainPageInChromium, ItsKernelExplainsAnyPixelAsOctraceExplainDoes) {
    const std::string chromium = findChromium();
    if (chromium.empty())
        GTEST_SKIP() << "no chromium on PATH (scripts/setup installs Debian's chromium)";
    struct Case {
        std::string scene, accel, pixels;
        std::vector<std::string> extra;
    };
    // Pixels on the model, on its silhouette, in the background and in a shadow.
    const std::vector<Case> cases = {
        {kMeshes + "/teapot.obj", "hash", "30,34;5,5;44,20;33,45", {}},
        {kMeshes + "/teapot.obj", "compact", "30,34;21,40;60,2", {"--max-depth", "5"}},
        {"grid:300", "linear", "32,32;10,40", {}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.scene + " " + c.accel);
        TempDir dir("kernel");
        const std::string page = dir.str("page.html");
        std::vector<std::string> args = {"explain", c.scene, "--size", "64x64",
                                         "--accel", c.accel, "--html", page};
        args.insert(args.end(), c.extra.begin(), c.extra.end());
        RunResult r = runOctrace(args, dir.path());
        if (r.status != 0 && r.err.find("without the page's viewer") != std::string::npos)
            GTEST_SKIP() << "octrace built with -DOCT_VIEWER=OFF";
        ASSERT_EQ(r.status, 0) << show(r);
        const nlohmann::json data = nlohmann::json::parse(dataOf(readFile(page)));
        if (data["kernel"].is_null())
            GTEST_SKIP() << "octrace built without emscripten: " << data["kernel_missing"];

        const Chromium run =
            runChromium(chromium, dir, "file://" + page + "#test=" + c.pixels, dir.str("s.png"));
        ASSERT_TRUE(run.ok) << run.log;
        EXPECT_NE(run.dom.find("data-kernel=\"ready\""), std::string::npos)
            << run.dom.substr(0, 4000) << "\n--- log ---\n"
            << run.log;
        EXPECT_NE(run.dom.find("<pre id=\"octrace-errors\"></pre>"), std::string::npos)
            << run.dom.substr(run.dom.find("octrace-errors"), 2000);
        const std::string open = "<pre id=\"octrace-test\">";
        const size_t a = run.dom.find(open);
        ASSERT_NE(a, std::string::npos) << "the page wrote no test output\n" << run.log;
        const size_t b = run.dom.find("</pre>", a);
        std::istringstream lines(
            unescapeText(run.dom.substr(a + open.size(), b - a - open.size())));
        size_t n = 0;
        double slowest = 0;
        for (std::string line; std::getline(lines, line);) {
            const nlohmann::json got = nlohmann::json::parse(line);
            const std::string pixel =
                std::to_string(got["x"].get<int>()) + "," + std::to_string(got["y"].get<int>());
            std::vector<std::string> want = {"explain", c.scene,   "--size", "64x64",  "--accel",
                                             c.accel,   "--pixel", pixel,    "--json", "-"};
            want.insert(want.end(), c.extra.begin(), c.extra.end());
            RunResult w = runOctrace(want, dir.path());
            ASSERT_EQ(w.status, 0) << show(w);
            EXPECT_EQ(got["json"].get<std::string>(), w.out) << "pixel " << pixel;
            // The page's 2D view is `octrace explain --svg`'s figure of that pixel.
            std::vector<std::string> svg = {
                "explain", c.scene,   "--size", "64x64", "--accel",
                c.accel,   "--pixel", pixel,    "--svg", dir.str("view.svg")};
            svg.insert(svg.end(), c.extra.begin(), c.extra.end());
            RunResult v = runOctrace(svg, dir.path());
            ASSERT_EQ(v.status, 0) << show(v);
            EXPECT_EQ(got["svg"].get<std::string>(), readFile(dir.str("view.svg")))
                << "pixel " << pixel;
            slowest = std::max(slowest, got["ms"].get<double>());
            ++n;
        }
        EXPECT_EQ(n, size_t(std::count(c.pixels.begin(), c.pixels.end(), ';') + 1));
        RecordProperty("click_ms_" + c.accel, std::to_string(slowest));
        std::printf("%s %s: slowest click %.1f ms, chromium %.1f s\n", c.scene.c_str(),
                    c.accel.c_str(), slowest, run.seconds);
    }
}

}  // namespace
}  // namespace oct
