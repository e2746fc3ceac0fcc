// Progress of a sweep on stderr: a bar on a terminal, a line per case otherwise.
#pragma once

#include <chrono>
#include <string>

namespace oct {

class Progress {
public:
    Progress(size_t total, bool enabled);

    // A case starts: a line per case when stderr is not a terminal.
    void begin(const std::string& label) { show(label, true); }
    // A step inside a case (loading, building): shown on a terminal only.
    void step(const std::string& label) { show(label, false); }
    void end() { ++done_; }
    // Clears the bar so a line can be printed on stdout (same terminal).
    void clear();
    double elapsed() const;

private:
    void show(const std::string& label, bool isCase);

    size_t total_, done_ = 0;
    bool enabled_, tty_;
    size_t lastWidth_ = 0;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace oct
