// Golden images (validation/regression/golden.h): the committed scenes rendered by this build, with
// every layout and with Embree's hits, against the images committed in tests/data/golden/; an image
// altered on purpose fails by the documented rule; the rule's boundaries; --update's report.
#include "validation/regression/golden.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "core/io/output_file.h"
#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/json_file.h"
#include "tests/paths.h"
#include "tests/validation/fixtures.h"
#include "validation/rays/ray_manifest.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using oct::GoldenReport;
using oct::GoldenRow;
using oct::ImageDiff;

using octtest::kRoot;
const std::string kGolden = OCT_SOURCE_DIR "/tests/data/golden";

using octtest::readJson;

// A copy of the golden folder listing only `file` (one image keeps the test fast).
void copyOne(const fs::path& to, const std::string& file) {
    json m = readJson(fs::path(kGolden) / "golden.json");
    json kept = json::array();
    for (const json& e : m["images"])
        if (e["file"] == file) kept.push_back(e);
    ASSERT_EQ(kept.size(), 1u) << file << " is not in golden.json";
    m["images"] = kept;
    std::ofstream(to / "golden.json") << m.dump(2);
    fs::copy_file(fs::path(kGolden) / file, to / file);
}

TEST(Golden, CommittedScenesMatchEveryLayoutAndEmbree) {
    const GoldenReport r = oct::checkGolden(kGolden, kRoot);
    EXPECT_TRUE(r.passes()) << oct::humanSummary(r);
    const size_t tracers = oct::layouts().size() + 1;  // + embree
    std::set<std::string> scenes;
    for (const GoldenRow& row : r.rows) {
        scenes.insert(row.scene);
        // Same build flags, same bits: the CPU kernel reproduces its own goldens exactly
        // (docs/VALIDATION.md, "Golden images"); the tolerance is for other builds and Embree.
        if (row.tracer != "embree") {
            EXPECT_EQ(row.diff.differing, 0u)
                << row.file << " " << row.tracer << ": max " << row.diff.maxDiff << "/255 at ("
                << row.diff.worstX << ", " << row.diff.worstY << ")";
        }
    }
    EXPECT_EQ(r.rows.size(), scenes.size() * tracers);
    // Every committed mesh and a generated cloud are pinned.
    for (const std::string& mesh : octtest::committedMeshes())
        EXPECT_TRUE(scenes.count("meshes/" + mesh)) << mesh << " has no golden image";
    EXPECT_TRUE(std::any_of(scenes.begin(), scenes.end(),
                            [](const std::string& s) { return s.rfind("grid:", 0) == 0; }));
}

// Alters `count` pixels of teapot's golden by `by` levels in the red channel.
GoldenReport checkAltered(int count, int by) {
    octtest::TempDir dir("golden_altered");
    copyOne(dir.path(), "teapot.obj.png");
    int w = 0, h = 0;
    const std::string png = dir.str("teapot.obj.png");
    std::vector<uint8_t> rgb = oct::readPngRgb(png, w, h);
    for (int i = 0; i < count; ++i) {
        uint8_t& r = rgb[3 * size_t(i * 7)];  // spread over the first rows
        r = uint8_t(r >= by ? r - by : r + by);
    }
    oct::writePng(png, w, h, rgb);
    return oct::checkGolden(dir.path().string(), kRoot);
}

TEST(Golden, AlteredImageFails) {
    // One pixel more than the rule allows (8 of 16384), off by 2/255: every tracer fails.
    const int tooMany = int(oct::GoldenTolerance{}.maxOverFraction * 128 * 128) + 1;
    GoldenReport r = checkAltered(tooMany, 2);
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.failures(), r.rows.size()) << oct::humanSummary(r);
    for (const GoldenRow& row : r.rows) EXPECT_GE(row.diff.over, uint64_t(tooMany)) << row.tracer;
    EXPECT_NE(oct::humanSummary(r).find("FAIL"), std::string::npos);
    EXPECT_FALSE(oct::toJson(r)["pass"].get<bool>());
    // An isolated pixel far off is allowed (a silhouette or shadow edge that another build
    // flips); one more than the rule allows fails.
    r = checkAltered(1, 100);
    EXPECT_TRUE(r.passes()) << oct::humanSummary(r);
    r = checkAltered(tooMany, 100);
    EXPECT_FALSE(r.passes()) << oct::humanSummary(r);
    for (const GoldenRow& row : r.rows) EXPECT_GE(row.diff.maxDiff, 100) << row.tracer;
    // 1/255 anywhere is within the rule (another compiler's rounding of a channel).
    r = checkAltered(500, 1);
    EXPECT_TRUE(r.passes()) << oct::humanSummary(r);
}

TEST(Golden, ToleranceRuleBoundaries) {
    const int w = 128, h = 128;
    const std::vector<uint8_t> a(3 * w * h, 100);
    const oct::GoldenTolerance rule;
    auto diffWith = [&](int pixels, int by) {
        std::vector<uint8_t> b = a;
        for (int i = 0; i < pixels; ++i) b[3 * i + 2] = uint8_t(100 + by);
        return oct::compareImages(w, h, a, b, rule.channel);
    };
    const uint64_t allowed = uint64_t(rule.maxOverFraction * w * h);  // 8
    ImageDiff d = diffWith(int(allowed), 2);
    EXPECT_EQ(d.over, allowed);
    EXPECT_TRUE(rule.passes(d));
    EXPECT_FALSE(rule.passes(diffWith(int(allowed) + 1, 2)));
    EXPECT_TRUE(rule.passes(diffWith(w * h, 1)));
    EXPECT_TRUE(rule.passes(diffWith(1, 155)));  // no cap on one pixel by default
    const oct::GoldenTolerance capped{1, 1e-3, 50};
    EXPECT_TRUE(capped.passes(diffWith(1, 50)));
    EXPECT_FALSE(capped.passes(diffWith(1, 51)));
    d = oct::compareImages(w, h, a, std::vector<uint8_t>(3 * w * (h - 1), 100), rule.channel);
    EXPECT_TRUE(d.sizeMismatch);
    EXPECT_FALSE(rule.passes(d));
}

TEST(Golden, UpdateRewritesAndSaysWhatChanged) {
    octtest::TempDir dir("golden_update");
    copyOne(dir.path(), "cube_binary.ply.png");
    const std::string png = dir.str("cube_binary.ply.png");
    int w = 0, h = 0;
    std::vector<uint8_t> rgb = oct::readPngRgb(png, w, h);
    for (int i = 0; i < 5; ++i) rgb[3 * i] ^= 0x40;
    oct::writePng(png, w, h, rgb);
    const GoldenReport u = oct::updateGolden(dir.path().string(), kRoot);
    ASSERT_EQ(u.rows.size(), 1u);
    EXPECT_EQ(u.rows[0].diff.differing, 5u);
    EXPECT_NE(oct::humanSummary(u).find("5 pixels changed"), std::string::npos)
        << oct::humanSummary(u);
    EXPECT_EQ(readJson(dir.path() / "golden.json")["octrace"], std::string(oct::octraceVersion()));
    // The rewritten image is the committed one again.
    EXPECT_EQ(oct::readPngRgb(png, w, h), oct::readPngRgb(kGolden + "/cube_binary.ply.png", w, h));
    EXPECT_TRUE(oct::checkGolden(dir.path().string(), kRoot).passes());
}

TEST(Golden, MissingManifestOrImageIsNamed) {
    octtest::TempDir dir("golden_missing");
    try {
        oct::checkGolden(dir.path().string(), kRoot);
        FAIL() << "no manifest accepted";
    } catch (const oct::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("golden.json"), std::string::npos) << e.what();
    }
    copyOne(dir.path(), "cube_binary.ply.png");
    fs::remove(dir.path() / "cube_binary.ply.png");
    try {
        oct::checkGolden(dir.path().string(), kRoot);
        FAIL() << "missing image accepted";
    } catch (const oct::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("cube_binary.ply.png"), std::string::npos) << e.what();
    }
}

}  // namespace
