#include "io/series_writer.hpp"

#include "solver/errors.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "io/atomic_file.hpp"

namespace vitrum {

SeriesWriter::SeriesWriter(const std::string& path, std::vector<std::string> columns)
    : path_(path), columns_(std::move(columns)), file_(std::fopen(path.c_str(), "w")) {
    if (!file_)
        throw RuntimeFailure("cannot open '" + path_ + "' for writing: " + std::strerror(errno));
    if (columns_.empty())
        throw RuntimeFailure("series '" + path_ + "' has no columns");
    for (std::size_t c = 0; c < columns_.size(); ++c) {
        // Names are written unquoted, so a separator or quote in one would shift every column after it.
        if (columns_[c].empty() || columns_[c].find_first_of(",\"\n\r") != std::string::npos)
            throw RuntimeFailure("series '" + path_ + "': bad column name '" + columns_[c] + "'");
        std::fprintf(file_.get(), c == 0 ? "%s" : ",%s", columns_[c].c_str());
    }
    std::fputc('\n', file_.get());
    flush(); // the header is on disk whatever happens to the process later
}

SeriesWriter::SeriesWriter(std::string path, std::vector<std::string> columns, std::FILE* file)
    : path_(std::move(path)), columns_(std::move(columns)), file_(file) {
    if (!file_)
        throw RuntimeFailure("cannot open '" + path_ + "' for appending: " + std::strerror(errno));
}

SeriesWriter SeriesWriter::continuing(const std::string& path, std::vector<std::string> columns, long through_step) {
    std::ifstream in(path);
    if (!in) {
        return SeriesWriter(path, std::move(columns));
    }
    std::string header;
    std::getline(in, header);
    std::string expected;
    for (const std::string& c : columns) {
        expected += (expected.empty() ? "" : ",") + c;
    }
    if (header != expected) {
        // The directory's content is the user's input to the restart: bad input (exit 2), like the checkpoint.
        throw InputError("cannot continue '" + path + "': its columns are not this run's (a series of another "
                         "scene?); move it away to start a new one");
    }
    std::string kept = header + "\n";
    const auto fields = [](const std::string& text) { return std::count(text.begin(), text.end(), ',') + 1; };
    std::string line;
    while (std::getline(in, line)) {
        // The first column is the step; the rows from the checkpoint's step on are recorded again. A line cut short
        // by a killed process (the last one, without its newline or its columns) is dropped.
        if (in.eof() || fields(line) != fields(header) ||
            std::strtod(line.c_str(), nullptr) >= static_cast<double>(through_step)) {
            break;
        }
        kept += line + "\n";
    }
    in.close();
    writeFileAtomically(path, kept);
    return SeriesWriter(path, std::move(columns), std::fopen(path.c_str(), "a"));
}

void SeriesWriter::row(std::span<const double> values) {
    if (values.size() != columns_.size())
        throw RuntimeFailure("series '" + path_ + "': row has " + std::to_string(values.size()) +
                             " values for " + std::to_string(columns_.size()) + " columns");
    for (std::size_t c = 0; c < values.size(); ++c)
        std::fprintf(file_.get(), c == 0 ? "%.10g" : ",%.10g", values[c]);
    std::fputc('\n', file_.get());
    if (std::ferror(file_.get()))
        throw RuntimeFailure("write to '" + path_ + "' failed");
}

void SeriesWriter::flush() {
    if (std::fflush(file_.get()) != 0 || std::ferror(file_.get()))
        throw RuntimeFailure("write to '" + path_ + "' failed: " + std::strerror(errno));
}

std::map<std::string, std::vector<double>> readSeries(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        throw RuntimeFailure("cannot read '" + path + "': " + std::strerror(errno));
    }
    std::string line;
    std::getline(in, line);
    std::vector<std::string> names;
    {
        std::istringstream header(line);
        for (std::string name; std::getline(header, name, ',');) names.push_back(name);
    }
    std::map<std::string, std::vector<double>> columns;
    for (const std::string& name : names) columns[name];
    long number = 1;
    while (std::getline(in, line)) {
        ++number;
        std::istringstream fields(line);
        std::size_t c = 0;
        for (std::string field; std::getline(fields, field, ','); ++c) {
            char* end = nullptr;
            const double v = std::strtod(field.c_str(), &end);
            if (c >= names.size() || end == field.c_str()) {
                throw RuntimeFailure(path + ":" + std::to_string(number) + ": not a row of the header's " +
                                     std::to_string(names.size()) + " numbers");
            }
            columns[names[c]].push_back(v);
        }
        if (c != names.size()) {
            throw RuntimeFailure(path + ":" + std::to_string(number) + ": " + std::to_string(c) + " values for " +
                                 std::to_string(names.size()) + " columns");
        }
    }
    return columns;
}

} // namespace vitrum
