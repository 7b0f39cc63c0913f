// series.csv (DESIGN.md §6): one header row of column names, then one row of numbers per probe sample.
#pragma once

#include <cstdio>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace vitrum {

/// CSV time series. Column names carry their unit (e.g. "time_ns", "force_N"); values are printed with
/// %.10g. Throws RuntimeFailure if the file cannot be opened or written, or a row has the wrong length.
/// The columns of a series.csv by name (numbers as written), for the measurements that read a run's history
/// back (the material test). Throws RuntimeFailure when the file cannot be read or a row is malformed.
std::map<std::string, std::vector<double>> readSeries(const std::string& path);

class SeriesWriter {
public:
    SeriesWriter(const std::string& path, std::vector<std::string> columns);
    /// Continues the series at `path` after a restart from step `through_step`: its rows before that step are
    /// kept (the header must be `columns`), the others dropped (the restarted run records them again, from the
    /// checkpoint's step on), and the new rows appended. A missing file starts afresh. Throws InputError when the
    /// header is not `columns`.
    static SeriesWriter continuing(const std::string& path, std::vector<std::string> columns, long through_step);
    void row(std::span<const double> values);
    /// Pushes buffered rows to the file, so the series can be read while the run goes on.
    void flush();
    const std::vector<std::string>& columns() const { return columns_; }

private:
    SeriesWriter(std::string path, std::vector<std::string> columns, std::FILE* file);
    struct FileCloser {
        void operator()(std::FILE* file) const { std::fclose(file); }
    };
    std::string path_;
    std::vector<std::string> columns_;
    std::unique_ptr<std::FILE, FileCloser> file_;
};

} // namespace vitrum
