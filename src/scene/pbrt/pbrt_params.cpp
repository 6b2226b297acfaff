#include "scene/pbrt/pbrt_params.h"

#include <charconv>
#include <cmath>
#include <limits>

namespace rayproc::pbrt {

namespace {

bool isNumericType(const std::string& t) {
    return t == "integer" || t == "float" || t == "point2" || t == "vector2" || t == "point3" ||
           t == "vector3" || t == "normal3" || t == "rgb" || t == "blackbody";
}

// How many numbers make one value of a numeric type.
std::size_t arity(const std::string& t) {
    if (t == "point2" || t == "vector2") return 2;
    if (t == "point3" || t == "vector3" || t == "normal3" || t == "rgb") return 3;
    return 1;
}

void addValue(Param& p, const Token& v) {
    if (isNumericType(p.type) || (p.type == "spectrum" && v.is(Token::Kind::Word))) {
        double x = 0;
        if (!v.is(Token::Kind::Word) || !parseNumber(v.text, x))
            failAt(v.loc, "parameter " + p.decl() + " expects numbers, got " + v.quoted());
        if (p.type == "integer" && (x != std::floor(x) || std::fabs(x) > 2147483647.0))
            failAt(v.loc, "parameter " + p.decl() + " expects integers, got " + v.quoted());
        p.numbers.push_back(x);
    } else if (p.type == "bool") {
        std::string_view s = v.text;
        if (s != "true" && s != "false")
            failAt(v.loc, "parameter " + p.decl() + " expects true or false, got " + v.quoted());
        p.bools.push_back(s == "true");
    } else { // string, texture, named spectrum
        if (!v.is(Token::Kind::String))
            failAt(v.loc, "parameter " + p.decl() + " expects quoted strings, got " + v.quoted());
        p.strings.push_back(Tokenizer::unescape(v));
    }
}

} // namespace

std::string normaliseParamType(std::string_view t) {
    if (t == "point") return "point3";
    if (t == "vector") return "vector3";
    if (t == "normal") return "normal3";
    if (t == "color") return "rgb";
    for (const char* k : {"integer", "float", "point2", "vector2", "point3", "vector3", "normal3",
                          "rgb", "spectrum", "blackbody", "bool", "string", "texture"})
        if (t == k) return k;
    return {};
}

bool parseNumber(std::string_view text, double& out) {
    if (!text.empty() && text[0] == '+') text.remove_prefix(1);
    if (text.empty() || text[0] == '+') return false;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    if (ec != std::errc() || end != text.data() + text.size()) return false;
    return std::isfinite(out) && std::fabs(out) <= double(std::numeric_limits<float>::max());
}

std::size_t Param::size() const {
    if (!numbers.empty()) return numbers.size() / arity(type);
    return !strings.empty() ? strings.size() : bools.size();
}

void ParamList::parse(Tokenizer& tok) {
    while (tok.peek().is(Token::Kind::String)) {
        Token declTok = tok.next();
        std::string decl = Tokenizer::unescape(declTok);
        std::size_t a = decl.find_first_not_of(" \t");
        std::size_t b = a == std::string::npos ? a : decl.find_first_of(" \t", a);
        std::size_t c = b == std::string::npos ? b : decl.find_first_not_of(" \t", b);
        std::size_t d = c == std::string::npos ? c : decl.find_first_of(" \t", c);
        if (c == std::string::npos ||
            (d != std::string::npos && decl.find_first_not_of(" \t", d) != std::string::npos))
            failAt(declTok.loc,
                   "expected a parameter declaration \"type name\", got \"" + decl + "\"");
        Param p;
        p.loc = declTok.loc;
        std::string rawType = decl.substr(a, b - a);
        p.type = normaliseParamType(rawType);
        p.name = decl.substr(c, d == std::string::npos ? std::string::npos : d - c);
        if (p.type.empty()) failAt(declTok.loc, "unknown parameter type \"" + rawType + "\"");
        if (find(p.name)) failAt(declTok.loc, "parameter \"" + p.name + "\" is given twice");

        if (tok.peek().is(Token::Kind::LBracket)) {
            Token open = tok.next();
            for (;;) {
                Token v = tok.next();
                if (v.is(Token::Kind::RBracket)) break;
                if (v.is(Token::Kind::End) || v.is(Token::Kind::LBracket))
                    failAt(open.loc, "\"[\" of parameter " + p.decl() + " is never closed");
                addValue(p, v);
            }
        } else {
            Token v = tok.next();
            if (!v.is(Token::Kind::Word) && !v.is(Token::Kind::String))
                failAt(v.loc, "expected a value for parameter " + p.decl() + ", got " + v.quoted());
            addValue(p, v);
        }
        if (p.numbers.empty() && p.strings.empty() && p.bools.empty())
            failAt(p.loc, "parameter " + p.decl() + " has no values");
        if (!p.numbers.empty() && p.numbers.size() % arity(p.type) != 0)
            failAt(p.loc, "parameter " + p.decl() + " expects a multiple of " +
                              std::to_string(arity(p.type)) + " numbers, got " +
                              std::to_string(p.numbers.size()));
        if (p.type == "spectrum" && !p.numbers.empty() && !p.strings.empty())
            failAt(p.loc, "parameter " + p.decl() + " mixes numbers and names");
        m_params.push_back(std::move(p));
    }
}

const Param* ParamList::find(std::string_view name) const {
    for (const Param& p : m_params)
        if (p.name == name) return &p;
    return nullptr;
}

const Param* ParamList::get(std::string_view name,
                            std::initializer_list<std::string_view> types) const {
    const Param* p = find(name);
    if (!p) return nullptr;
    for (std::string_view t : types) {
        if (p->type == t) {
            p->used = true;
            return p;
        }
    }
    std::string expected;
    for (std::string_view t : types)
        expected += (expected.empty() ? "\"" : " or \"") + std::string(t) + "\"";
    failAt(p->loc, "parameter \"" + p->name + "\" must be of type " + expected + ", not \"" +
                       p->type + "\"");
}

const Param* ParamList::single(std::string_view name, std::string_view type) const {
    const Param* p = get(name, {type});
    if (p && p->size() != 1)
        failAt(p->loc,
               "parameter " + p->decl() + " expects one value, got " + std::to_string(p->size()));
    return p;
}

double ParamList::getFloat(std::string_view name, double def) const {
    const Param* p = single(name, "float");
    return p ? p->numbers[0] : def;
}

long long ParamList::getInt(std::string_view name, long long def) const {
    const Param* p = single(name, "integer");
    return p ? static_cast<long long>(p->numbers[0]) : def;
}

bool ParamList::getBool(std::string_view name, bool def) const {
    const Param* p = single(name, "bool");
    return p ? p->bools[0] != 0 : def;
}

std::string ParamList::getString(std::string_view name, const std::string& def) const {
    const Param* p = single(name, "string");
    return p ? p->strings[0] : def;
}

Vec3 ParamList::getPoint3(std::string_view name, Vec3 def) const {
    const Param* p = single(name, "point3");
    if (!p) return def;
    return {float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2])};
}

Vec3 ParamList::getVector3(std::string_view name, Vec3 def) const {
    const Param* p = single(name, "vector3");
    if (!p) return def;
    return {float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2])};
}

void ParamList::ignore(std::initializer_list<std::string_view> names) const {
    for (std::string_view n : names)
        if (const Param* p = find(n)) p->used = true;
}

std::vector<const Param*> ParamList::unused() const {
    std::vector<const Param*> out;
    for (const Param& p : m_params)
        if (!p.used) out.push_back(&p);
    return out;
}

} // namespace rayproc::pbrt
