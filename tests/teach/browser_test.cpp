// The explain page in a real browser: headless Chromium (Debian's chromium, installed by
// scripts/setup) opens the file octrace wrote, from file:// with no network, with software WebGL
// (SwiftShader). One run dumps the DOM after the page's script ran and takes a screenshot:
// the page must say it rendered, list every step, report no script error, and the screenshot
// must show a picture with the primary ray's magenta in it. Skips only without a Chromium.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>

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

    const std::string shot = dir.str("shot.png"), dom = dir.str("dom.html"),
                      log = dir.str("chromium.log");
    const std::vector<std::string> args = {
        chromium, "--headless", "--no-sandbox", "--disable-dev-shm-usage",
        // WebGL without a GPU: SwiftShader, Chromium's software GL.
        "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
        // No network, no first-run work, a fresh profile.
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run", "--disable-default-apps", "--user-data-dir=" + dir.str("profile"),
        "--enable-logging=stderr", "--v=0", "--hide-scrollbars", "--window-size=800,600",
        "--screenshot=" + shot, "--dump-dom", "file://" + page};
    std::string cmd = "timeout 90 ";
    for (const std::string& a : args) cmd += quote(a) + " ";
    cmd += ">" + quote(dom) + " 2>" + quote(log);
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(cmd.c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    RecordProperty("chromium_seconds", std::to_string(seconds));
    std::printf("chromium took %.2f s\n", seconds);
    const std::string domText = readFile(dom), logText = readFile(log);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "chromium failed (status " << status << ")\n"
        << logText;

    // The page's own report (its first script catches errors and console.error calls).
    EXPECT_NE(domText.find("data-octrace=\"rendered\""), std::string::npos)
        << domText.substr(0, 3000) << "\n--- log ---\n"
        << logText;
    EXPECT_NE(domText.find("<pre id=\"octrace-errors\"></pre>"), std::string::npos)
        << "the page reported errors:\n"
        << domText.substr(domText.find("octrace-errors"), 2000);
    EXPECT_EQ(logText.find("Uncaught"), std::string::npos) << logText;
    EXPECT_EQ(count(domText, "<li class=\"step"), steps) << "the step list is incomplete";
    EXPECT_NE(domText.find("<canvas"), std::string::npos) << "no WebGL canvas";

    // The screenshot: a picture (many colours), the primary ray's magenta in it.
    int w = 0, h = 0, channels = 0;
    stbi_uc* px = stbi_load(shot.c_str(), &w, &h, &channels, 3);
    ASSERT_NE(px, nullptr) << "no screenshot\n" << logText;
    EXPECT_EQ(w, 800);
    EXPECT_EQ(h, 600);
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

}  // namespace
}  // namespace oct
