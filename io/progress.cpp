#include "io/progress.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

namespace vitrum {
namespace {

constexpr double redraw_interval_s = 0.2; // a terminal redrawn faster than ~5 Hz only flickers

} // namespace

std::string formatDuration(double seconds) {
    const long total = std::isfinite(seconds) && seconds > 0 ? std::lround(seconds) : 0;
    char text[32];
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
    return text;
}

std::string formatProgress(long step, long total, double elapsed_s, const std::string& probes, bool bound,
                           long first_step) {
    const double percent = total > 0 ? 100.0 * static_cast<double>(step) / static_cast<double>(total) : 100.0;
    char head[96];
    std::snprintf(head, sizeof head, "[%5.1f%%] step %ld/%ld  ", percent, step, total);
    std::string line = head;
    if (step > first_step && elapsed_s > 0) {
        const double rate = static_cast<double>(step - first_step) / elapsed_s;
        char tail[64];
        std::snprintf(tail, sizeof tail, bound ? "%.0f steps/s  ETA <= " : "%.0f steps/s  ETA ", rate);
        line += tail;
        line += formatDuration(static_cast<double>(total - step) / rate);
    } else {
        line += "- steps/s  ETA -";
    }
    if (!probes.empty())
        line += "  | " + probes;
    return line;
}

ProgressReporter::ProgressReporter(std::ostream& out, bool interactive, long total_steps,
                                   double report_interval_s, Clock now_s)
    : out_(out), interactive_(interactive), total_steps_(total_steps), report_interval_s_(report_interval_s),
      now_s_(std::move(now_s)) {
    if (!now_s_)
        now_s_ = [] {
            return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
        };
    start_s_ = now_s_();
    last_report_s_ = start_s_;
}

void ProgressReporter::update(long step, const std::string& probes) {
    last_step_ = step;
    last_probes_ = probes;
    const double now = now_s_();
    if (now - last_report_s_ < (interactive_ ? redraw_interval_s : report_interval_s_))
        return;
    last_report_s_ = now;
    emit(formatProgress(step, total_steps_, now - start_s_, probes, eta_is_bound_, first_step_));
}

void ProgressReporter::finish() {
    if (finished_)
        return;
    finished_ = true;
    emit(formatProgress(last_step_, total_steps_, now_s_() - start_s_, last_probes_, eta_is_bound_,
                        first_step_));
    if (interactive_)
        out_ << '\n';
    out_.flush();
}

void ProgressReporter::emit(const std::string& line) {
    if (interactive_) {
        // Pad with blanks so a shorter line fully covers the previous, longer one.
        out_ << '\r' << line;
        if (line.size() < drawn_length_)
            out_ << std::string(drawn_length_ - line.size(), ' ');
        drawn_length_ = line.size();
        out_.flush();
    } else {
        out_ << line << std::endl; // flushed: a batch log followed with tail -f shows it at once
    }
}

} // namespace vitrum
