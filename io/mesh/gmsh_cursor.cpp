#include "io/mesh/gmsh_cursor.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "io/mesh/gmsh_error.hpp"

namespace ifsim::io {

GmshCursor::GmshCursor(std::string text, std::string file)
    : text_(std::move(text)), file_(std::move(file)) {}

void GmshCursor::skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
        if (text_[pos_] == '\n') {
            ++line_;
        }
        ++pos_;
    }
}

std::string_view GmshCursor::raw_token() {
    skip_space();
    token_line_ = line_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) {
        ++pos_;
    }
    return std::string_view(text_).substr(start, pos_ - start);
}

std::string_view GmshCursor::next_or_end() {
    return raw_token();
}

std::string_view GmshCursor::token(std::string_view what) {
    const std::string_view t = raw_token();
    if (t.empty()) {
        fail(fmt::format("truncated {} section: expected {}, found the end of the file", section_,
                         what));
    }
    if (t.front() == '$') {
        fail(fmt::format("truncated {} section: expected {}, found '{}'", section_, what, t));
    }
    return t;
}

long long GmshCursor::integer(std::string_view what, long long lo, long long hi) {
    const std::string_view t = token(what);
    long long v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size()) {
        fail(fmt::format("expected {} (an integer) in the {} section, found '{}'", what, section_,
                         t));
    }
    if (v < lo || v > hi) {
        fail(fmt::format("expected {} from {} to {} in the {} section, found {}", what, lo, hi,
                         section_, v));
    }
    return v;
}

double GmshCursor::real(std::string_view what) {
    const std::string_view t = token(what);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v)) {
        fail(fmt::format("expected {} (a finite number) in the {} section, found '{}'", what,
                         section_, t));
    }
    return v;
}

void GmshCursor::skip_real(std::string_view what) {
    const std::string_view t = token(what);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    const bool number = ec == std::errc() || ec == std::errc::result_out_of_range;
    if (!number || end != t.data() + t.size()) {
        fail(
            fmt::format("expected {} (a number) in the {} section, found '{}'", what, section_, t));
    }
}

std::string GmshCursor::quoted(std::string_view what) {
    skip_space();
    token_line_ = line_;
    if (pos_ >= text_.size() || text_[pos_] != '"') {
        const std::string_view t = token(what);
        fail(fmt::format("expected {} in double quotes in the {} section, found '{}'", what,
                         section_, t));
    }
    const std::size_t start = ++pos_;
    while (pos_ < text_.size() && text_[pos_] != '"' && text_[pos_] != '\n') {
        ++pos_;
    }
    if (pos_ >= text_.size() || text_[pos_] != '"') {
        fail(fmt::format("expected the closing '\"' of {} on the same line", what));
    }
    return text_.substr(start, pos_++ - start);
}

void GmshCursor::expect_end() {
    const std::string end = "$End" + section_.substr(1);
    const std::string_view t = raw_token();
    if (t != end) {
        fail(fmt::format("expected '{}' closing the {} section, found {}", end, section_,
                         t.empty() ? std::string("the end of the file") : fmt::format("'{}'", t)));
    }
    section_.clear();
}

void GmshCursor::skip_section() {
    const std::string end = "$End" + section_.substr(1);
    const int start = token_line_;
    for (std::string_view t = raw_token(); t != end; t = raw_token()) {
        if (t.empty()) {
            fail_at(start, fmt::format("the {} section has no closing '{}'", section_, end));
        }
    }
    section_.clear();
}

void GmshCursor::fail(const std::string& message) const {
    fail_at(token_line_, message);
}

void GmshCursor::fail_at(int line, const std::string& message) const {
    throw MeshFileError(file_, line, message);
}

} // namespace ifsim::io
