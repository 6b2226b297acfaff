#include "scene/pbrt/pbrt_tokenizer.h"

#include "core/error.h"

namespace rayproc::pbrt {

std::string SourceLoc::str() const {
    return (file ? *file : std::string("?")) + ":" + std::to_string(line) + ":" +
           std::to_string(column);
}

std::string SourceLoc::fileAndLine() const {
    return (file ? *file : std::string("?")) + ":" + std::to_string(line);
}

std::string quote(std::string_view s) {
    std::string out;
    out.reserve(s.size() + 2);
    out += '"';
    out += s;
    out += '"';
    return out;
}

void failAt(const SourceLoc& loc, const std::string& problem) {
    throw InputError(loc.str() + ": " + problem);
}

std::string Token::quoted() const {
    switch (kind) {
    case Kind::End:
        return "the end of the file";
    case Kind::LBracket:
        return "\"[\"";
    case Kind::RBracket:
        return "\"]\"";
    case Kind::String:
        return "the string " + quote(text);
    case Kind::Word:
        break;
    }
    return quote(text);
}

Tokenizer::Tokenizer(std::string_view text, const std::string* file) : m_text(text), m_file(file) {
    // A UTF-8 byte order mark is not part of the scene.
    if (m_text.substr(0, 3) == "\xEF\xBB\xBF") m_pos = m_lineStart = 3;
}

const Token& Tokenizer::peek() {
    if (!m_hasPeeked) {
        m_peeked = scan();
        m_hasPeeked = true;
    }
    return m_peeked;
}

Token Tokenizer::next() {
    if (m_hasPeeked) {
        m_hasPeeked = false;
        return m_peeked;
    }
    return scan();
}

void Tokenizer::skipSpaceAndComments() {
    const std::size_t n = m_text.size();
    while (m_pos < n) {
        char c = m_text[m_pos];
        if (c == '\n') {
            ++m_line;
            m_lineStart = ++m_pos;
        } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
            ++m_pos;
        } else if (c == '#') {
            while (m_pos < n && m_text[m_pos] != '\n') ++m_pos;
        } else {
            return;
        }
    }
}

Token Tokenizer::scan() {
    skipSpaceAndComments();
    Token t;
    t.loc = {m_file, m_line, int(m_pos - m_lineStart) + 1};
    const std::size_t n = m_text.size();
    if (m_pos >= n) return t; // End
    char c = m_text[m_pos];
    if (c == '[' || c == ']') {
        t.kind = c == '[' ? Token::Kind::LBracket : Token::Kind::RBracket;
        t.text = m_text.substr(m_pos++, 1);
        return t;
    }
    if (c == '"') {
        // pbrt strings stay on one line; an escaped quote does not end them.
        std::size_t start = ++m_pos;
        while (m_pos < n && m_text[m_pos] != '"') {
            if (m_text[m_pos] == '\n') break;
            m_pos += m_text[m_pos] == '\\' && m_pos + 1 < n && m_text[m_pos + 1] != '\n' ? 2 : 1;
        }
        if (m_pos >= n || m_text[m_pos] != '"') failAt(t.loc, "unterminated string");
        t.kind = Token::Kind::String;
        t.text = m_text.substr(start, m_pos - start);
        ++m_pos;
        return t;
    }
    std::size_t start = m_pos;
    while (m_pos < n) {
        char d = m_text[m_pos];
        if (d == ' ' || d == '\n' || d == '\t' || d == '\r' || d == '\f' || d == '\v' || d == '"' ||
            d == '[' || d == ']' || d == '#')
            break;
        ++m_pos;
    }
    t.kind = Token::Kind::Word;
    t.text = m_text.substr(start, m_pos - start);
    return t;
}

std::string Tokenizer::unescape(const Token& t) {
    std::string out;
    out.reserve(t.text.size());
    for (std::size_t i = 0; i < t.text.size(); ++i) {
        char c = t.text[i];
        if (c != '\\' || i + 1 >= t.text.size()) {
            out += c;
            continue;
        }
        char e = t.text[++i];
        switch (e) {
        case 'n':
            out += '\n';
            break;
        case 't':
            out += '\t';
            break;
        case 'b':
            out += '\b';
            break;
        case 'f':
            out += '\f';
            break;
        case 'r':
            out += '\r';
            break;
        default:
            out += e;
            break; // \\ \" \' and anything else stand for themselves
        }
    }
    return out;
}

} // namespace rayproc::pbrt
