#pragma once
// Reading a Gmsh ASCII mesh file token by token with line numbers: every accessor returns a
// valid value or throws MeshFileError naming the file, the line and what was expected. Inside
// a section a '$' token where data was expected means the section is truncated.

#include <string>
#include <string_view>

namespace ifsim::io {

class GmshCursor {
public:
    GmshCursor(std::string text, std::string file);

    const std::string& file() const { return file_; }
    // Line of the last token read (1-based).
    int line() const { return token_line_; }

    // The section being read ("$Nodes"), for messages; "" between sections.
    void enter(std::string_view section) { section_ = section; }
    // The next token, or "" at the end of the file (between sections).
    std::string_view next_or_end();
    // The next data token; throws at the end of the file or at a '$' token.
    std::string_view token(std::string_view what);
    long long integer(std::string_view what, long long lo, long long hi);
    double real(std::string_view what);
    // A number whose value is not used (entity bounding boxes): Gmsh writes +-DBL_MAX to 16
    // digits for entities without geometry, which rounds past the largest double.
    void skip_real(std::string_view what);
    // A double-quoted string on one line ("soil zone").
    std::string quoted(std::string_view what);
    // The section's closing token "$End<name>"; throws naming what was found instead.
    void expect_end();
    // Skips a section whose header was read, up to and including its "$End<name>".
    void skip_section();

    [[noreturn]] void fail(const std::string& message) const;
    [[noreturn]] void fail_at(int line, const std::string& message) const;

private:
    void skip_space();
    std::string_view raw_token();

    std::string text_;
    std::string file_;
    std::string section_;
    std::size_t pos_ = 0;
    int line_ = 1;
    int token_line_ = 0;
};

} // namespace ifsim::io
