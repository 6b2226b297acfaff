#include "bench/results_csv.h"

#include "core/error.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

namespace rayproc::bench {

namespace {

std::string formatDouble(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

// Splits one CSV record (RFC 4180 quoting) into fields.
std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                fields.back() += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                fields.back() += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            fields.emplace_back();
        } else if (c != '\r') {
            fields.back() += c;
        }
    }
    return fields;
}

double parseDouble(const std::string& s, const std::string& where) {
    try {
        std::size_t used = 0;
        double v = std::stod(s, &used);
        if (used == s.size()) return v;
    } catch (const std::exception&) {
    }
    throw InputError(where + ": '" + s + "' is not a number");
}

} // namespace

std::string quoteCsvField(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string formatCsvRow(const BenchRow& r) {
    return quoteCsvField(r.scene) + "," + quoteCsvField(r.mode) + "," + quoteCsvField(r.settings) + "," +
           formatDouble(r.seconds) + "," + std::to_string(r.rays) + "," + formatDouble(r.relmse) +
           "," + formatDouble(r.rmse);
}

std::string settingValue(const std::string& settings, const std::string& key) {
    std::istringstream in(settings);
    std::string token;
    while (in >> token)
        if (token.size() > key.size() && token.compare(0, key.size() + 1, key + "=") == 0)
            return token.substr(key.size() + 1);
    return "";
}

std::string settingsWithout(const std::string& settings, const std::string& key) {
    std::istringstream in(settings);
    std::string token, out;
    while (in >> token)
        if (token.compare(0, key.size() + 1, key + "=") != 0) out += (out.empty() ? "" : " ") + token;
    return out;
}

ResultsCsvWriter::ResultsCsvWriter(const std::string& path, bool truncate)
    : m_path(path), m_truncate(truncate) {}

void ResultsCsvWriter::open() {
    std::error_code ec;
    bool fresh = m_truncate || !std::filesystem::exists(m_path, ec) ||
                 std::filesystem::file_size(m_path, ec) == 0;
    m_out.open(m_path, m_truncate ? std::ios::trunc : std::ios::app);
    if (!m_out) throw InputError(m_path + ": cannot open for writing");
    if (fresh) m_out << kResultsCsvHeader << "\n" << std::flush;
    if (!m_out) throw InputError(m_path + ": cannot write");
}

void ResultsCsvWriter::append(const BenchRow& row) {
    if (!m_out.is_open()) open();
    m_out << formatCsvRow(row) << "\n" << std::flush;
    if (!m_out) throw InputError(m_path + ": cannot write");
}

std::vector<BenchRow> parseResultsCsv(const std::string& text, const std::string& path) {
    std::istringstream in(text);
    std::string line;
    int lineNo = 0;
    std::vector<BenchRow> rows;
    std::map<std::string, std::size_t> column;
    const char* required[] = {"scene", "mode", "settings", "seconds", "rays", "relmse", "rmse"};
    std::size_t width = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        std::vector<std::string> f = splitCsvLine(line);
        std::string where = path + ": line " + std::to_string(lineNo);
        if (column.empty()) {
            for (std::size_t i = 0; i < f.size(); ++i) column[f[i]] = i;
            for (const char* name : required)
                if (!column.count(name))
                    throw InputError(where + ": no '" + name + "' column (expected the header " +
                                     kResultsCsvHeader + ")");
            width = f.size();
            continue;
        }
        if (f.size() != width)
            throw InputError(where + ": " + std::to_string(f.size()) + " fields, the header has " +
                             std::to_string(width));
        BenchRow r;
        r.scene = f[column["scene"]];
        r.mode = f[column["mode"]];
        r.settings = f[column["settings"]];
        r.seconds = parseDouble(f[column["seconds"]], where);
        double rays = parseDouble(f[column["rays"]], where);
        r.rays = rays > 0 ? std::uint64_t(rays) : 0;
        r.relmse = parseDouble(f[column["relmse"]], where);
        r.rmse = parseDouble(f[column["rmse"]], where);
        rows.push_back(r);
    }
    if (column.empty()) throw InputError(path + ": empty (expected the header " +
                                         std::string(kResultsCsvHeader) + ")");
    return rows;
}

std::vector<BenchRow> readResultsCsv(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open");
    std::stringstream ss;
    ss << in.rdbuf();
    return parseResultsCsv(ss.str(), path);
}

} // namespace rayproc::bench
