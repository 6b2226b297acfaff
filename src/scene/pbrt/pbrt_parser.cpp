#include "scene/pbrt/pbrt_parser.h"

#include "core/error.h"
#include "scene/pbrt/mapped_file.h"
#include "scene/pbrt/pbrt_shapes.h"

#include <memory>
#include <vector>

namespace rayproc::pbrt {

namespace {

constexpr std::size_t kMaxIncludeDepth = 64;

class Parser {
public:
    Parser(SceneBuilder& builder, std::deque<std::string>& names, const std::string& mainPath)
        : m_builder(builder), m_names(names),
          m_mainDir(std::filesystem::path(mainPath).parent_path()) {}

    void push(std::string_view text, const std::string& name, std::unique_ptr<MappedFile> file) {
        m_names.push_back(name);
        auto s = std::make_unique<Source>(Source{std::move(file), Tokenizer(text, &m_names.back()),
                                                 std::filesystem::path(name).parent_path()});
        m_sources.push_back(std::move(s));
    }

    void run() {
        for (;;) {
            Token t = tok().next();
            if (t.is(Token::Kind::End)) {
                if (m_sources.size() == 1) return;
                m_sources.pop_back(); // back in the including file
                continue;
            }
            if (!t.is(Token::Kind::Word)) failAt(t.loc, "expected a directive, got " + t.quoted());
            directive(t);
        }
    }

private:
    struct Source {
        std::unique_ptr<MappedFile> file; // null for text given in memory
        Tokenizer tok;
        std::filesystem::path dir;
    };

    Tokenizer& tok() { return m_sources.back()->tok; }

    std::string string(const Token& d, const char* what) {
        Token t = tok().next();
        if (!t.is(Token::Kind::String))
            failAt(t.loc,
                   std::string(d.text) + " expects a quoted " + what + ", got " + t.quoted());
        return Tokenizer::unescape(t);
    }

    double number(const Token& d) {
        Token t = tok().next();
        double v = 0;
        if (!t.is(Token::Kind::Word) || !parseNumber(t.text, v))
            failAt(t.loc, std::string(d.text) + " expects a number, got " + t.quoted());
        return v;
    }

    // n numbers, optionally in brackets (Transform and ConcatTransform are written both ways).
    void numbers(const Token& d, std::size_t n, double* out) {
        bool bracket = tok().peek().is(Token::Kind::LBracket);
        if (bracket) tok().next();
        for (std::size_t i = 0; i < n; ++i) {
            if (bracket && tok().peek().is(Token::Kind::RBracket))
                failAt(tok().peek().loc, std::string(d.text) + " expects " + std::to_string(n) +
                                             " numbers, got " + std::to_string(i));
            out[i] = number(d);
        }
        if (bracket) {
            Token t = tok().next();
            if (!t.is(Token::Kind::RBracket))
                failAt(t.loc, std::string(d.text) + " expects " + std::to_string(n) +
                                  " numbers and \"]\", got " + t.quoted());
        }
    }

    ParamList params() {
        ParamList p;
        p.parse(tok());
        return p;
    }

    void transform(const Token& d, bool concat) {
        double v[16];
        numbers(d, 16, v);
        if (m_ignoreTransforms) return;
        Mat4 m = Mat4::fromPbrt(v);
        if (concat)
            m_builder.concat(m);
        else
            m_builder.setTransform(m);
    }

    void include(const Token& d) {
        std::string name = string(d, "file name");
        if (m_sources.size() >= kMaxIncludeDepth)
            failAt(d.loc, "Include nested more than " + std::to_string(kMaxIncludeDepth) +
                              " levels deep (does a file include itself?)");
        if (name.size() > 3 && name.substr(name.size() - 3) == ".gz")
            failAt(d.loc, "compressed scene files (.gz) are not supported: " + name);
        std::filesystem::path p = resolvePath(name, m_sources.back()->dir, m_mainDir);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec))
            failAt(d.loc, "cannot open the included file " + p.string());
        auto file = std::make_unique<MappedFile>(p.string());
        std::string_view text = file->data();
        push(text, p.string(), std::move(file));
    }

    void directive(const Token& d);
    // Each handles its directives and says whether d was one of them.
    bool sceneDirective(const Token& d);     // shapes, materials, textures, lights, media
    bool blockDirective(const Token& d);     // attribute, object and world blocks, includes
    bool transformDirective(const Token& d); // the current transform
    bool optionDirective(const Token& d);    // camera, film, sampler and other render options

    SceneBuilder& m_builder;
    std::deque<std::string>& m_names;
    std::filesystem::path m_mainDir;
    std::vector<std::unique_ptr<Source>> m_sources;
    bool m_ignoreTransforms = false; // ActiveTransform EndTime: motion is not supported
};

void Parser::directive(const Token& d) {
    if (sceneDirective(d) || blockDirective(d) || transformDirective(d) || optionDirective(d))
        return;
    failAt(d.loc, "unknown directive \"" + std::string(d.text) + "\"");
}

bool Parser::sceneDirective(const Token& d) {
    const std::string_view n = d.text;
    const SourceLoc& loc = d.loc;
    SceneBuilder& b = m_builder;
    if (n == "Shape") {
        std::string type = string(d, "shape type");
        b.shape(type, params(), loc, m_sources.back()->dir);
    } else if (n == "Material") {
        std::string type = string(d, "material type");
        b.material(type, params(), loc);
    } else if (n == "MakeNamedMaterial") {
        std::string name = string(d, "material name");
        b.makeNamedMaterial(name, params(), loc);
    } else if (n == "NamedMaterial") {
        b.namedMaterial(string(d, "material name"), loc);
    } else if (n == "Texture") {
        std::string name = string(d, "texture name");
        std::string type = string(d, "texture type");
        std::string cls = string(d, "texture class");
        b.texture(name, type, cls, params(), loc);
    } else if (n == "LightSource") {
        std::string type = string(d, "light type");
        b.lightSource(type, params(), loc);
    } else if (n == "AreaLightSource") {
        std::string type = string(d, "area light type");
        b.areaLightSource(type, params(), loc);
    } else if (n == "MakeNamedMedium") {
        std::string name = string(d, "medium name");
        b.makeNamedMedium(name, params(), loc);
    } else if (n == "MediumInterface") {
        std::string inside = string(d, "medium name"), outside = inside;
        if (tok().peek().is(Token::Kind::String)) outside = string(d, "medium name");
        b.mediumInterface(inside, outside, loc);
    } else {
        return false;
    }
    return true;
}

bool Parser::blockDirective(const Token& d) {
    const std::string_view n = d.text;
    const SourceLoc& loc = d.loc;
    SceneBuilder& b = m_builder;
    if (n == "AttributeBegin" || n == "TransformBegin") {
        b.begin(n == "AttributeBegin" ? "Attribute" : "Transform", loc);
    } else if (n == "AttributeEnd" || n == "TransformEnd") {
        b.end(n == "AttributeEnd" ? "Attribute" : "Transform", loc);
    } else if (n == "ObjectBegin") {
        b.objectBegin(string(d, "object name"), loc);
    } else if (n == "ObjectEnd") {
        b.objectEnd(loc);
    } else if (n == "ObjectInstance") {
        b.objectInstance(string(d, "object name"), loc);
    } else if (n == "Include" || n == "Import") {
        include(d);
    } else if (n == "WorldBegin") {
        b.worldBegin(loc);
    } else if (n == "WorldEnd") {
        b.worldEnd(loc);
    } else {
        return false;
    }
    return true;
}

bool Parser::transformDirective(const Token& d) {
    const std::string_view n = d.text;
    const SourceLoc& loc = d.loc;
    SceneBuilder& b = m_builder;
    auto xform = [&](auto&& f) {
        if (!m_ignoreTransforms) f();
    };
    if (n == "Identity") {
        xform([&] { b.identity(); });
    } else if (n == "Translate" || n == "Scale") {
        double v[3];
        for (double& x : v) x = number(d);
        xform([&] {
            b.concat(n == "Translate" ? Mat4::translate(v[0], v[1], v[2])
                                      : Mat4::scale(v[0], v[1], v[2]));
        });
    } else if (n == "Rotate") {
        double v[4];
        for (double& x : v) x = number(d);
        xform([&] { b.rotate(v[0], {v[1], v[2], v[3]}, loc); });
    } else if (n == "LookAt") {
        double v[9];
        for (double& x : v) x = number(d);
        xform([&] { b.lookAt(v, loc); });
    } else if (n == "Transform" || n == "ConcatTransform") {
        transform(d, n == "ConcatTransform");
    } else if (n == "CoordinateSystem") {
        b.coordinateSystem(string(d, "name"));
    } else if (n == "CoordSysTransform") {
        std::string name = string(d, "name");
        xform([&] { b.coordSysTransform(name, loc); });
    } else if (n == "ReverseOrientation") {
        b.reverseOrientation();
    } else if (n == "ActiveTransform") {
        Token t = tok().next();
        if (!t.is(Token::Kind::Word) ||
            (t.text != "StartTime" && t.text != "EndTime" && t.text != "All"))
            failAt(t.loc, "ActiveTransform expects StartTime, EndTime or All, got " + t.quoted());
        m_ignoreTransforms = t.text == "EndTime";
        if (m_ignoreTransforms)
            b.unsupported("Motion blur", "the transforms at the start time are used", loc);
    } else if (n == "TransformTimes") {
        number(d);
        number(d);
    } else {
        return false;
    }
    return true;
}

bool Parser::optionDirective(const Token& d) {
    const std::string_view n = d.text;
    const SourceLoc& loc = d.loc;
    SceneBuilder& b = m_builder;
    if (n == "Camera") {
        std::string type = string(d, "camera type");
        b.camera(type, params(), loc);
    } else if (n == "Film") {
        string(d, "film type"); // rgb, gbuffer, spectral: rayproc's film is RGB
        b.film(params(), loc);
    } else if (n == "Sampler") {
        std::string type = string(d, "sampler type");
        b.sampler(type, params(), loc);
    } else if (n == "Integrator") {
        // The render mode chooses the algorithm; sppm's photon settings go to gi.
        std::string type = string(d, "integrator type");
        b.integrator(type, params(), loc);
    } else if (n == "Accelerator") {
        string(d, "accelerator type"); // Embree builds its own
        b.requireOptions("Accelerator", loc);
        params();
    } else if (n == "PixelFilter") {
        std::string type = string(d, "filter type");
        b.pixelFilter(type, params(), loc);
    } else if (n == "ColorSpace") {
        b.colorSpace(string(d, "colour space"), loc);
    } else if (n == "Option") {
        params();
        b.unsupported("Option", "ignored", loc);
    } else if (n == "Attribute") {
        string(d, "attribute target");
        params();
        b.unsupported("Attribute (default parameters)", "ignored", loc);
    } else {
        return false;
    }
    return true;
}

} // namespace

void parsePbrt(std::string_view text, const std::string& path, SceneBuilder& builder,
               std::deque<std::string>& names) {
    Parser parser(builder, names, path);
    parser.push(text, path, nullptr);
    parser.run();
}

} // namespace rayproc::pbrt
