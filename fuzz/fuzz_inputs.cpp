// libFuzzer target over the readers of certify's and trace's other inputs (docs/ROBUSTNESS.md):
// the ray file, a .npy file, a hit-file pair and a ray manifest.
//
// Input: one selector byte (% 4), then the bytes:
//   0  a ray file:       readRayFile; every row it returns must pass rayRowProblem
//   1  a .npy file:      readNpy; the data it returns must fill its shape exactly
//   2  a hit-file pair:  two bytes n (little-endian, the t file's length), then P.t.npy (n
//                        bytes) and P.prim.npy (the rest); readHitFiles for as many rays as
//                        the t file claims (at most 1 << 20), with ids and without
//   3  a ray manifest:   readManifest, then checkManifestRows against 1000 rows
// IoError is the expected refusal (nlohmann's parse errors are turned into it by the readers).
// Anything else is a finding: a crash, a sanitizer report, another exception, a hang
// (-timeout) or an allocation past -rss_limit_mb / -malloc_limit_mb.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/io/npy.h"
#include "core/io/output_file.h"
#include "core/io/ray_file.h"
#include "fuzz/fuzz_files.h"
#include "validation/rays/hit_files.h"
#include "validation/rays/ray_manifest.h"

namespace {

void fuzzRayFile(const std::string& path) {
    const std::vector<float> rays = oct::readRayFile(path);
    if (rays.size() % 8 != 0) std::abort();
    for (size_t i = 0; i < rays.size(); i += 8)
        if (!oct::rayRowProblem(&rays[i]).empty()) std::abort();  // a row trace would refuse
}

void fuzzNpy(const std::string& path) {
    const oct::NpyArray a = oct::readNpy(path, "the fuzzed file");
    uint64_t n = 1;
    for (uint64_t d : a.shape) n *= d;
    (void)n;  // readNpy checks the data size against the shape; the sanitizers check the rest
}

void fuzzHitPair(const std::string& dir, const uint8_t* data, size_t size) {
    if (size < 2) return;
    const size_t n = std::min<size_t>(size - 2, data[0] | size_t(data[1]) << 8);
    const std::string prefix = dir + "/P";
    fuzz::writeFile(oct::hitTPath(prefix), data + 2, n);
    fuzz::writeFile(oct::hitPrimPath(prefix), data + 2 + n, size - 2 - n);
    // The row count the t file's bytes suggest (4 bytes a row after a short header), so that
    // the length check is passed as often as it is failed.
    const uint64_t rays = std::min<uint64_t>(n > 128 ? (n - 128) / 4 : n / 4, 1u << 20);
    for (bool ids : {true, false}) {
        try {
            const oct::HitArrays h = oct::readHitFiles(prefix, rays, "R.npy", ids);
            if (h.count() != rays || (ids && h.prim.size() != rays)) std::abort();
        } catch (const oct::IoError&) {
        }
    }
    std::remove(oct::hitTPath(prefix).c_str());
    std::remove(oct::hitPrimPath(prefix).c_str());
}

void fuzzManifest(const std::string& path) {
    const oct::RayManifest m = oct::readManifest(path);
    oct::checkManifestRows(m, 1000, "R.npy");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string& dir = fuzz::scratchDir();
    const int kind = data[0] % 4;
    const std::string path = dir + (kind == 3 ? "/R.json" : "/input.npy");
    try {
        if (kind == 2) {
            fuzzHitPair(dir, data + 1, size - 1);
            return 0;
        }
        fuzz::writeFile(path, data + 1, size - 1);
        if (kind == 0) fuzzRayFile(path);
        if (kind == 1) fuzzNpy(path);
        if (kind == 3) fuzzManifest(path);
    } catch (const oct::IoError&) {
    }
    std::remove(path.c_str());
    return 0;
}
