#include "io/output/history_writer.hpp"

#include <iterator>
#include <system_error>

#include <stdexcept>
#include <unistd.h>

namespace ifsim::io {

HistoryWriter::HistoryWriter(const std::filesystem::path& dir, std::vector<std::string> columns)
    : dir_(dir), columns_(std::move(columns)) {
    const auto path = dir_ / partial_name;
    file_ = std::fopen(path.c_str(), "w");
    if (file_ == nullptr) {
        throw std::runtime_error(fmt::format("cannot write {}", path.string()));
    }
    std::string header;
    for (const auto& c : columns_) {
        header += (header.empty() ? "" : ",") + c;
    }
    fmt::print(file_, "{}\n", header);
}

HistoryWriter::HistoryWriter(const std::filesystem::path& dir, std::vector<std::string> columns,
                             ResumeAt at)
    : dir_(dir), columns_(std::move(columns)), rows_(at.rows) {
    const auto path = dir_ / partial_name;
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec || static_cast<long long>(size) < at.bytes) {
        throw std::runtime_error(fmt::format(
            "cannot resume {}: {} (the checkpoint saw {} bytes)", path.string(),
            ec ? ec.message() : fmt::format("the file has only {} bytes", size), at.bytes));
    }
    std::filesystem::resize_file(path, static_cast<std::uintmax_t>(at.bytes), ec);
    file_ = ec ? nullptr : std::fopen(path.c_str(), "a");
    if (file_ == nullptr) {
        throw std::runtime_error(fmt::format("cannot resume {}", path.string()));
    }
}

long long HistoryWriter::sync() {
    if (file_ == nullptr || std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) {
        throw std::runtime_error(fmt::format("cannot write {}", (dir_ / partial_name).string()));
    }
    return static_cast<long long>(std::ftell(file_));
}

HistoryWriter::~HistoryWriter() {
    if (file_ != nullptr) {
        std::fclose(file_); // unfinished: the .partial file stays as evidence
    }
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
    if (std::fwrite(line_.data(), 1, line_.size(), file_) != line_.size()) {
        throw std::runtime_error(fmt::format("cannot write {}", (dir_ / partial_name).string()));
    }
    line_.clear();
    in_row_ = 0;
    ++rows_;
}

void HistoryWriter::finish() {
    if (file_ == nullptr) {
        return;
    }
    const bool ok = std::fflush(file_) == 0;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) {
        throw std::runtime_error(fmt::format("cannot write {}", (dir_ / partial_name).string()));
    }
    std::filesystem::rename(dir_ / partial_name, dir_ / file_name);
}

} // namespace ifsim::io
