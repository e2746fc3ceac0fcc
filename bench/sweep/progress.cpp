#include "bench/sweep/progress.h"

#include <unistd.h>

#include <cstdio>

namespace oct {

Progress::Progress(size_t total, bool enabled)
    : total_(total),
      enabled_(enabled),
      tty_(isatty(2) != 0),
      start_(std::chrono::steady_clock::now()) {}

void Progress::clear() {
    if (enabled_ && tty_ && lastWidth_) {
        std::fprintf(stderr, "\r%s\r", std::string(lastWidth_, ' ').c_str());
        std::fflush(stderr);
        lastWidth_ = 0;
    }
}

double Progress::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::show(const std::string& label, bool isCase) {
    if (!enabled_ || (!tty_ && !isCase)) return;
    double s = elapsed();
    char head[96];
    std::snprintf(head, sizeof head, "[%zu/%zu %dm%02ds] ", done_ + 1, total_, int(s) / 60,
                  int(s) % 60);
    if (tty_) {
        const int width = 24;
        int filled = total_ ? int(double(done_) / double(total_) * width) : 0;
        std::string bar(size_t(filled), '#');
        bar.resize(size_t(width), '.');
        std::string line = "\r" + bar + " " + head + label;
        if (line.size() < lastWidth_) line += std::string(lastWidth_ - line.size(), ' ');
        lastWidth_ = line.size();
        std::fputs(line.c_str(), stderr);
    } else {
        std::fprintf(stderr, "%s%s\n", head, label.c_str());
    }
    std::fflush(stderr);
}

}  // namespace oct
