// Run progress on the console: a redrawn line on a terminal, plain periodic lines in logs and batch jobs.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace vitrum {

/// `[ 42.0%] step 4200/10000  1234 steps/s  ETA 0:04:42  | <probes>`. The rate is the mean over this
/// process so far, (step - first_step) / elapsed_s, where first_step is the step the process started from
/// (0, or a restart's checkpoint step: the steps an earlier process ran took none of elapsed_s); before any
/// step or time has passed, rate and ETA print as "-". The "  | probes" tail is left out when probes is
/// empty. `bound`: the total is an upper bound (a run that ends on a condition), printed "ETA <= ...".
std::string formatProgress(long step, long total, double elapsed_s, const std::string& probes,
                           bool bound = false, long first_step = 0);

/// h:mm:ss, seconds rounded to the nearest and negatives clamped to 0.
std::string formatDuration(double seconds);

class ProgressReporter {
public:
    /// Seconds since an arbitrary origin; injectable so tests can drive time.
    using Clock = std::function<double()>;

    /// `interactive`: out is a terminal (the caller decides, e.g. with isatty); then one line is redrawn
    /// with '\r' at most 5 times a second. Otherwise a plain line is written every report_interval_s.
    /// `now_s` defaults to std::chrono::steady_clock.
    ProgressReporter(std::ostream& out, bool interactive, long total_steps, double report_interval_s = 10.0,
                     Clock now_s = {});
    void update(long step, const std::string& probes);
    /// The total is an upper bound (the run ends on a condition, e.g. the last indentation stage).
    void setTotalIsBound(bool bound) { eta_is_bound_ = bound; }
    /// The step this process starts from (a restart's checkpoint step): the rate counts the steps after it.
    void setFirstStep(long step) { first_step_ = last_step_ = step; }
    /// Always writes the final line (ending the redrawn one with a newline). Further calls do nothing.
    void finish();

private:
    void emit(const std::string& line);

    std::ostream& out_;
    bool interactive_;
    long total_steps_;
    double report_interval_s_;
    Clock now_s_;
    double start_s_;
    double last_report_s_;
    long last_step_ = 0;
    std::string last_probes_;
    std::size_t drawn_length_ = 0;
    bool finished_ = false;
    bool eta_is_bound_ = false;
    long first_step_ = 0;
};

} // namespace vitrum
