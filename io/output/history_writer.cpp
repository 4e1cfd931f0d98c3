#include "io/output/history_writer.hpp"

#include <cerrno>
#include <iterator>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

namespace ifsim::io {

HistoryWriter::HistoryWriter(const std::filesystem::path& dir, std::vector<std::string> columns)
    : dir_(dir), columns_(std::move(columns)) {
    const auto path = dir_ / partial_name;
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        throw std::runtime_error(fmt::format("cannot write {}", path.string()));
    }
    for (const auto& c : columns_) {
        if (line_.size() > 0) {
            line_.push_back(',');
        }
        line_.append(c);
    }
    line_.push_back('\n');
    write_line();
}

HistoryWriter::HistoryWriter(const std::filesystem::path& dir, std::vector<std::string> columns,
                             ResumeAt at)
    : dir_(dir), columns_(std::move(columns)), rows_(at.rows) {
    const auto path = dir_ / partial_name;
    std::error_code ec;
    // A run stopped by a signal or a failure handed its rows over as history.csv: they become
    // the partial file again.
    if (!std::filesystem::exists(path, ec) && std::filesystem::exists(dir_ / file_name, ec)) {
        std::filesystem::rename(dir_ / file_name, path, ec);
    }
    const auto size = std::filesystem::file_size(path, ec);
    if (ec || static_cast<long long>(size) < at.bytes) {
        throw std::runtime_error(fmt::format(
            "cannot resume {}: {} (the checkpoint saw {} bytes)", path.string(),
            ec ? ec.message() : fmt::format("the file has only {} bytes", size), at.bytes));
    }
    std::filesystem::resize_file(path, static_cast<std::uintmax_t>(at.bytes), ec);
    fd_ = ec ? -1 : ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0) {
        throw std::runtime_error(fmt::format("cannot resume {}", path.string()));
    }
}

long long HistoryWriter::sync() {
    const off_t end = fd_ < 0 ? -1 : ::lseek(fd_, 0, SEEK_END);
    if (end < 0 || ::fsync(fd_) != 0) {
        throw std::runtime_error(fmt::format("cannot write {}", (dir_ / partial_name).string()));
    }
    return static_cast<long long>(end);
}

HistoryWriter::~HistoryWriter() {
    if (fd_ >= 0) {
        ::close(fd_); // unfinished: the .partial file stays as evidence
    }
}

// One write(2) per row (a short write is continued): a run killed at any moment leaves whole
// rows, never half of one, and an interrupted run can hand its rows over as they are.
void HistoryWriter::write_line() {
    const char* p = line_.data();
    std::size_t left = line_.size();
    while (left > 0) {
        const ssize_t n = ::write(fd_, p, left);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            throw std::runtime_error(
                fmt::format("cannot write {}", (dir_ / partial_name).string()));
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    line_.clear();
}

void HistoryWriter::separator() {
    if (in_row_ > 0) {
        line_.push_back(',');
    }
    ++in_row_;
}

void HistoryWriter::integer(long long value) {
    separator();
    fmt::format_to(std::back_inserter(line_), "{}", value);
}

void HistoryWriter::real(double value) {
    separator();
    fmt::format_to(std::back_inserter(line_), "{}", value);
}

void HistoryWriter::empty() {
    separator();
}

void HistoryWriter::end_row() {
    if (in_row_ != columns_.size()) {
        throw std::logic_error(
            fmt::format("history row with {} fields for {} columns", in_row_, columns_.size()));
    }
    line_.push_back('\n');
    write_line();
    in_row_ = 0;
    ++rows_;
}

void HistoryWriter::finish() {
    if (fd_ < 0) {
        return;
    }
    const bool closed = ::close(fd_) == 0;
    fd_ = -1;
    if (!closed) {
        throw std::runtime_error(fmt::format("cannot write {}", (dir_ / partial_name).string()));
    }
    std::filesystem::rename(dir_ / partial_name, dir_ / file_name);
}

} // namespace ifsim::io
