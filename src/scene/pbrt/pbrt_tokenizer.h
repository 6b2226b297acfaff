// pbrt-v4's text format, lexically: quoted strings, bare words (directives, numbers, true and
// false), brackets, and '#' comments to the end of the line. The tokenizer walks a file held in
// memory without copying it; every token knows its line and column, so that every message can
// say "file:line:column".
#pragma once

#include <string>
#include <string_view>

namespace rayproc::pbrt {

// A place in a scene file. `file` points into storage the loader keeps alive (one string per
// file read), so locations stay cheap to copy.
struct SourceLoc {
    const std::string* file = nullptr;
    int line = 0;
    int column = 0;
    std::string str() const;         // "file:line:column"
    std::string fileAndLine() const; // "file:line" (warnings)
};

// `s` in double quotes, for messages.
std::string quote(std::string_view s);

// "file:line:column: problem" as an InputError.
[[noreturn]] void failAt(const SourceLoc& loc, const std::string& problem);

struct Token {
    enum class Kind { End, Word, String, LBracket, RBracket };
    Kind kind = Kind::End;
    std::string_view text; // a String's contents without the quotes, escapes unresolved
    SourceLoc loc;

    bool is(Kind k) const { return kind == k; }
    std::string quoted() const; // for messages: "[", a word, or the string in quotes
};

class Tokenizer {
public:
    // `text` and `*file` must outlive the tokenizer.
    Tokenizer(std::string_view text, const std::string* file);

    Token next();
    const Token& peek();

    // A String token's value with pbrt's escapes (\" \\ \n \t \b \f \r \') resolved.
    static std::string unescape(const Token& t);

private:
    void skipSpaceAndComments();
    Token scan();

    std::string_view m_text;
    const std::string* m_file;
    std::size_t m_pos = 0;
    int m_line = 1;
    std::size_t m_lineStart = 0;
    Token m_peeked;
    bool m_hasPeeked = false;
};

} // namespace rayproc::pbrt
