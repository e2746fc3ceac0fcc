// The validation report in two forms with the same content: a human summary for stdout and a
// JSON object (field names as in docs/VALIDATION.md: `wrong`, `ambiguous`,
// `replication.false_negatives`, ...).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "validation/table1.h"
#include "validation/validate.h"

namespace oct {

nlohmann::json toJson(const ClassCounts& c);
nlohmann::json toJson(const ReplicationReport& r);
nlohmann::json toJson(const ValidationReport& r);
nlohmann::json toJson(const std::vector<Table1Row>& rows);

std::string humanSummary(const ReplicationReport& r);
std::string humanSummary(const ValidationReport& r);
std::string humanTable1(const std::vector<Table1Row>& rows);

}  // namespace oct
