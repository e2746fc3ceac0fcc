// Performance baselines (`octrace bench --baseline FILE`): each case's frame time as a ratio to
// Embree's frame on the same scene in the same run, and its traversal cost per pixel, stored in a
// JSON file and compared with a new sweep. The ratio is measured in pairs of frames, each on the
// process's CPU clock (SweepOptions::pairedReference), so machine speed and other people's work
// on a shared machine cancel; counts are deterministic. The file's fields, the measured spread
// behind the threshold and how to update: bench/README.md, "Performance baselines".
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/sweep/results.h"

namespace oct {

constexpr const char* kBaselineFormat = "octrace-bench-baseline";
constexpr int kBaselineVersion = 1;

// The rule. Time: a case fails when its ratio to Embree grew by more than the factor. The run-to-
// run spread of the ratio on this project's 2-core machine (bench/baseline-spread, 16 runs of
// bench/baselines/cpu.json at a load of 8, every pair of runs compared, 1440 changes): 95th
// percentile of |log change| 0.098, largest 0.168 (x1.18); during `ctest -j2` of the whole suite
// (15 runs) the largest change against the file was 0.141. The factor is twice the largest,
// e^0.336 = 1.40 (bench/README.md, "Performance baselines", has every run). Counts: fail above
// +5 %, as the cost baselines of `validate --cost-baseline` (validation/regression).
constexpr double kBaselineTimeFactor = 1.40;
constexpr double kBaselineCountTolerance = 0.05;

struct BaselineRule {
    double timeFactor = kBaselineTimeFactor;
    double countTolerance = kBaselineCountTolerance;
};

// One case of a baseline: a layout of ours on a backend that traces it, on one scene. Counts are
// per pixel (the primary and the shadow ray of each pixel): the denominator is fixed by --size,
// so they move only when the traversal's work does (per ray would divide by the shadow rays
// cast, which move with the hits).
struct BaselineCase {
    std::string scene, layout, backend;  // as bench's rows name them
    double ratioToEmbree = 0.0, nodesPerPixel = 0.0, primsPerPixel = 0.0;
};

// The file: format and version, the octrace that wrote it, the machine (for information only),
// the bench options the values depend on (`options`, keys as bench's options without the
// dashes) and the cases.
struct BaselineFile {
    std::string octrace;
    nlohmann::ordered_json machine, options;
    std::vector<BaselineCase> cases;
};

// The options that must be equal for values to compare (a file made with another is refused),
// in the order checked; the lists (clouds, meshes, layouts, backends) only choose the cases.
const std::vector<std::string>& baselineMatchedOptions();

// Reads FILE; throws IoError, one line naming the file and what to do, when it is missing,
// unreadable, not JSON, of another format or version, or lacks a field.
BaselineFile readBaseline(const std::string& path);
nlohmann::ordered_json baselineJson(const BaselineFile& b);
// Writes FILE whole (a temporary renamed when complete).
void writeBaseline(const std::string& path, const BaselineFile& b);

// The cases a sweep measured: its "ok" rows on backends that trace our layouts.
std::vector<BaselineCase> baselineCases(const std::vector<Row>& rows);

// The first option of baselineMatchedOptions whose value in `run` differs from `stored`, as
// "--size 128x128, but FILE was made with --size 256x256"; empty when all are equal.
std::string optionMismatch(const nlohmann::ordered_json& stored, const nlohmann::ordered_json& run,
                           const std::string& file);

enum class CaseOutcome {
    Compared,  // in the file and measured: time and counts judged
    Missing,   // measured, not in the file: fails (the file needs --update)
    Stale,     // in the file, not asked for in this run: a note
    Skipped,   // in the file, asked for, but not measured here (a backend not available, a mesh
               // not found, a row skipped by the sweep): the verdict is INCOMPLETE
    Error,     // asked for, and the sweep's row is an error: fails
};
// Each compared case's time and counts: Same (within the rule), Worse (fails), Better (a note:
// the file is out of date).
enum class Change { Same, Worse, Better };

struct CaseComparison {
    std::string scene, layout, backend;
    CaseOutcome outcome = CaseOutcome::Compared;
    std::optional<BaselineCase> stored, now;
    std::string why;                              // Skipped and Error: the reason
    double timeFactor = 1.0;                      // now's ratio / the stored ratio
    double nodesChange = 0.0, primsChange = 0.0;  // now / stored - 1
    Change time = Change::Same, counts = Change::Same;
    bool fails() const {
        return outcome == CaseOutcome::Missing || outcome == CaseOutcome::Error ||
               time == Change::Worse || counts == Change::Worse;
    }
};

// What stops cases from being measured here, by scene (a mesh of the file not found) or by
// backend (asked for, not available): name -> why. Either makes the verdict INCOMPLETE at best.
struct NotRun {
    std::map<std::string, std::string> scenes, backends;
};

struct BaselineReport {
    std::string file;
    BaselineRule rule;
    std::vector<CaseComparison> cases;
    NotRun notRun;
    size_t count(CaseOutcome o) const;
    size_t slower() const;            // cases whose time failed
    size_t costlier() const;          // cases whose counts failed
    bool fails() const;               // any case fails
    bool incomplete() const;          // nothing fails, something was skipped or not run
    std::string failureText() const;  // "2 slower (time), 1 more nodes or prims (counts)"
};

// Judges a sweep's rows against the stored cases: a measured case against its stored one
// (Compared) or without one (Missing); a stored case without a measured one is Skipped when its
// scene or backend is in `notRun` or the sweep skipped its row, Error when its row (or its
// scene's loading) is an error, else Stale. A row the sweep skipped that the file lacks is not
// a case.
BaselineReport compareBaseline(const std::string& file, const std::vector<BaselineCase>& stored,
                               const std::vector<Row>& rows, const NotRun& notRun,
                               const BaselineRule& rule = {});

// The report as text: a line per case, worst first, then the notes and the totals.
std::string humanSummary(const BaselineReport& r);

}  // namespace oct
