#!/usr/bin/env python3
"""scripts/check-structure on crafted trees: it measures functions through comments, strings,
raw strings, digit separators, macros, lambdas, class bodies and initializer lists as the
docs say; it fails on a function of 81 lines and passes one of 80; it fails on an include of
gi/ or modes/ from src/engine/ and of modes/ from src/gi/ (relative paths too); and its
exceptions file lets a listed violation pass but fails a listed function that grew and a
listed entry that no longer violates. Run by ctest (structure_check_selftest):
    tests/scripts/test_check_structure.py
"""
import importlib.machinery
import importlib.util
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOL = os.path.join(ROOT, "scripts", "check-structure")

loader = importlib.machinery.SourceFileLoader("check_structure", TOOL)
spec = importlib.util.spec_from_loader("check_structure", loader)
cs = importlib.util.module_from_spec(spec)
loader.exec_module(cs)

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


TRICKY = r'''#include "engine/x.h"
#define BRACE {   \
    }  }
namespace rayproc {
namespace {
const char* kText = "}{ not a brace \" }";
const char* kRaw = R"x(
} ) " {
)x";
constexpr int kBig = 1'000'000;
char open() { return '{'; }  // }
/* } { */
struct Table { int a; int b; };
const Table kTable[] = {{1, 2},
                        {3, 4}};
auto kLambda = [](int x) {
    return x + 1;
};
}  // namespace

class Widget : public Base<int> {
  public:
    Widget(int a) : m_a{a}, m_b(a) {
        m_c = a;
    }
    int get() const noexcept { return m_a; }
    bool operator==(const Widget& o) const {
        return m_a == o.m_a;
    }
    struct Inner {
        void f() {}
    };

  private:
    int m_a{0};
    std::function<void(int)> m_cb{};
};

template <typename T>
std::vector<T> Widget::collect(T x) const {
    auto f = [&](int y) {
        struct Local { int g() { return 1; } };
        return y;
    };
    return {x};
}
enum class Colour { Red, Green };
}  // namespace rayproc
extern "C" {
__attribute__((visibility("default"))) void*
exported(int x) {
    return nullptr;
}
}
'''

EXPECTED = {"open": 1, "kLambda": 3, "Widget::Widget": 3, "Widget::get": 1,
            "Widget::operator==": 3, "Widget::Inner::f": 1, "Widget::collect": 7, "exported": 3}


def test_measure():
    found = {fn.name: fn.length for fn in cs.functions_of(TRICKY)}
    check(found == EXPECTED, "measured %s, expected %s" % (found, EXPECTED))
    starts = {fn.name: fn.start for fn in cs.functions_of(TRICKY)}
    check(starts.get("Widget::collect") == 40, "collect starts on %s, not its name's line 40"
          % starts.get("Widget::collect"))


def long_function(name, lines):
    """A function of exactly `lines` lines, counted from its name to its closing brace."""
    body = ["    x += %d;  // { a brace in a comment" % k for k in range(lines - 3)]
    return "int %s(int x) {\n%s\n    return x;\n}\n" % (name, "\n".join(body))


def make_tree(files, exceptions=None):
    tmp = tempfile.mkdtemp()
    for rel, text in files.items():
        path = os.path.join(tmp, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
    os.makedirs(os.path.join(tmp, "scripts"), exist_ok=True)
    with open(os.path.join(tmp, "scripts", "structure-exceptions.txt"), "w") as f:
        f.write("# crafted\n" + "".join(line + "\n" for line in (exceptions or [])))
    return tmp


def run(files, exceptions=None):
    root = make_tree(files, exceptions)
    p = subprocess.run([sys.executable, TOOL, "--root", root], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    return p.returncode, p.stdout


def test_length_limit():
    rc, out = run({"src/engine/ok.cpp": long_function("fits", 80)})
    check(rc == 0, "80 lines should pass: %s" % out)
    rc, out = run({"src/engine/long.cpp": long_function("tooLong", 81)})
    check(rc == 1 and "tooLong is 81 lines" in out, "81 lines should fail: %s" % out)
    # Inside a class body in a header, too.
    header = "struct Big {\n" + long_function("member", 90) + "};\n"
    rc, out = run({"src/core/big.h": header})
    check(rc == 1 and "Big::member is 90 lines" in out, "an inline member of 90 lines: %s" % out)


def test_includes():
    for rel, inc, bad in (("src/engine/a.cpp", "gi/gather_stage.h", True),
                          ("src/engine/a.h", "modes/render_job.h", True),
                          ("src/engine/a.cpp", "../modes/render_job.h", True),
                          ("src/gi/a.cpp", "modes/render_job.h", True),
                          ("src/gi/a.cpp", "engine/processor.h", False),
                          ("src/modes/a.cpp", "gi/gather_stage.h", False)):
        rc, out = run({rel: '#include "%s"\nint f() { return 0; }\n' % inc,
                       "src/modes/render_job.h": "", "src/gi/gather_stage.h": "",
                       "src/engine/processor.h": ""})
        check(rc == (1 if bad else 0), "%s including %s: exit %d: %s" % (rel, inc, rc, out))
    # An include inside a comment is no include.
    rc, out = run({"src/engine/a.cpp": '/*\n#include "gi/x.h"\n*/\n'})
    check(rc == 0, "an include in a comment: %s" % out)


def test_exceptions():
    files = {"src/gi/long.cpp": long_function("tooLong", 90),
             "src/engine/a.cpp": '#include "gi/x.h"\n'}
    listed = ["function src/gi/long.cpp tooLong 90", "include src/engine/a.cpp gi/x.h"]
    rc, out = run(files, listed)
    check(rc == 0, "listed violations should pass: %s" % out)
    rc, out = run(files, ["function src/gi/long.cpp tooLong 89", listed[1]])
    check(rc == 1 and "grew to 90" in out, "a listed function that grew: %s" % out)
    rc, out = run(files, ["function src/gi/long.cpp tooLong 95", listed[1]])
    check(rc == 0 and "shrank to 90" in out, "a listed function that shrank: %s" % out)
    rc, out = run({"src/gi/long.cpp": long_function("tooLong", 80),
                   "src/engine/a.cpp": files["src/engine/a.cpp"]}, listed)
    check(rc == 1 and "remove the line" in out, "a listed function now short: %s" % out)
    rc, out = run({"src/gi/long.cpp": files["src/gi/long.cpp"], "src/engine/a.cpp": ""}, listed)
    check(rc == 1 and "which is gone" in out, "a listed include now gone: %s" % out)
    rc, out = run(files, listed + ["nonsense line"])
    check(rc == 1, "a malformed exceptions line: %s" % out)


def test_unparsable():
    rc, out = run({"src/engine/a.cpp": "void f() {\n"})
    check(rc == 2 and "cannot parse" in out, "an unclosed brace: %s" % out)


def test_this_tree():
    p = subprocess.run([sys.executable, TOOL], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    check(p.returncode in (0, 1) and "cannot parse" not in p.stdout,
          "src/ itself must parse: %s" % p.stdout)


for test in (test_measure, test_length_limit, test_includes, test_exceptions, test_unparsable,
             test_this_tree):
    test()
for f in failures:
    print("FAIL: " + f)
print("check-structure self-test: %d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
