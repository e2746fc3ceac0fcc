// certify's per-ray verdicts as files (docs/CERTIFY.md, "Per-ray verdicts"), one entry per row
// of the ray file: PREFIX.class.npy uint8 (HitClass: 0 agree, 1 tie, 2 ambiguous, 3 wrong,
// 4 unverified), PREFIX.reasons.npy uint32 (AmbiguityReason bits) and PREFIX.leak.npy uint8
// (LeakState: 0 sealed, 1 leak, 2 not a target, 3 unsealed, 4 unverified).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace oct {

struct VerdictArrays {
    std::vector<uint8_t> cls;
    std::vector<uint32_t> reasons;
    std::vector<uint8_t> leak;
};

std::string verdictClassPath(const std::string& prefix);    // PREFIX.class.npy
std::string verdictReasonsPath(const std::string& prefix);  // PREFIX.reasons.npy
std::string verdictLeakPath(const std::string& prefix);     // PREFIX.leak.npy

// Writes the three files as one unit (all or none: core/io/output_file.h).
void writeVerdictFiles(const std::string& prefix, const VerdictArrays& v);
// Reads them back for `rows` rows; throws IoError naming the file for a missing one, another
// dtype or shape, another length, or a class or leak value outside its enum.
VerdictArrays readVerdictFiles(const std::string& prefix, uint64_t rows);

}  // namespace oct
