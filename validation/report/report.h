// The validation report in two forms with the same content: a human summary for stdout and a
// JSON object (field names as in docs/VALIDATION.md: `wrong`, `ambiguous`,
// `replication.false_negatives`, ...).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "validation/certify.h"
#include "validation/validate.h"

namespace oct {

nlohmann::json toJson(const ClassCounts& c);
nlohmann::json toJson(const ReplicationReport& r);
nlohmann::json toJson(const ValidationReport& r);

std::string humanSummary(const ReplicationReport& r);
std::string humanSummary(const ValidationReport& r);
// What failed, for the one-line error: "3 wrong, 0 ambiguous, 2 replication false negatives,
// ..." (every check's clause, validation/checks/check.h).
std::string failureText(const ValidationReport& r);

// The per-ray check (certify.h), shared by validate's and certify's reports: counts per set,
// reasons, the first wrong and ambiguous rays, the leaks.
nlohmann::json toJson(const RayCertification& r, double maxAmbiguousRate);
std::string humanRaySets(const RayCertification& r, double maxAmbiguousRate);
// `octrace certify` (certify_report.cpp).
nlohmann::json toJson(const CertifyReport& r);
std::string humanSummary(const CertifyReport& r);

}  // namespace oct
