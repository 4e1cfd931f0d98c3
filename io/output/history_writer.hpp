#pragma once
// history.csv of a run, one row per step. Rows go to DIR/history.csv.partial while the run
// is going and the file is renamed to history.csv by finish() (also after a failed run, whose
// rows are kept; summary.json says it failed), so a file named history.csv is never one that
// is still being written. Each row goes to the file in one write(2): a killed run's file ends
// in a whole row. Numbers are written in the shortest form that reads back to the
// same double.

#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace ifsim::io {

class HistoryWriter {
public:
    // Creates DIR/history.csv.partial and writes the header. Throws std::runtime_error naming
    // the file when it cannot be written.
    HistoryWriter(const std::filesystem::path& dir, std::vector<std::string> columns);
    ~HistoryWriter();
    HistoryWriter(const HistoryWriter&) = delete;
    HistoryWriter& operator=(const HistoryWriter&) = delete;

    // Continues the history.csv.partial of a killed run from a checkpoint (or the history.csv
    // of a run stopped by a signal, renamed back): the file is cut back to `bytes` (what the
    // checkpoint saw; rows written after it are dropped) holding `rows` rows. Throws
    // std::runtime_error naming the file when it is missing or shorter.
    struct ResumeAt {
        long long bytes = 0;
        std::size_t rows = 0;
    };
    HistoryWriter(const std::filesystem::path& dir, std::vector<std::string> columns, ResumeAt at);

    // Flushes the rows so far to disk (fsync) and returns the file's length in bytes: what a
    // checkpoint records.
    long long sync();

    void integer(long long value);
    void real(double value);
    // An empty field: a quantity the run does not have (documented per kind).
    void empty();
    // Ends the row; throws std::logic_error when the row has the wrong number of fields.
    void end_row();

    // Closes the file and renames it to history.csv. Throws std::runtime_error on I/O errors.
    void finish();

    std::size_t rows() const { return rows_; }
    const std::vector<std::string>& columns() const { return columns_; }

    static constexpr const char* file_name = "history.csv";
    static constexpr const char* partial_name = "history.csv.partial";

private:
    void separator();
    void write_line();

    std::filesystem::path dir_;
    std::vector<std::string> columns_;
    int fd_ = -1;
    std::size_t in_row_ = 0;
    std::size_t rows_ = 0;
    fmt::memory_buffer line_;
};

} // namespace ifsim::io
