// results.csv: one row per bench render, appended and flushed as each render finishes, so an
// interrupted run keeps every result so far. Columns (header on the first line):
//
//   scene,mode,settings,seconds,rays,relmse,rmse
//
// `settings` is space-separated key=value pairs ("spp=16", "spp=4 gather=64 ic=0.25
// photons=200000"); `seconds` is the render's wall time, `rays` every ray handed to Embree,
// relmse and rmse against the scene's reference (docs/image-comparison.md). Peer renderers'
// CSVs (--peer-csv) use the same columns.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace rayproc::bench {

struct BenchRow {
    std::string scene;    // the scene file's stem ("cornell-box")
    std::string mode;     // preview, raytrace, gi, path, or a peer renderer's name
    std::string settings; // "spp=16 ..."
    double seconds = 0;
    std::uint64_t rays = 0;
    double relmse = 0;
    double rmse = 0;
};

inline const char* kResultsCsvHeader = "scene,mode,settings,seconds,rays,relmse,rmse";

// A CSV field, quoted (RFC 4180) when it holds a comma, quote or line break.
std::string quoteCsvField(const std::string& field);

// One CSV line (no newline) with fields quoted where they hold a comma, quote or newline, and
// numbers at full precision (17 significant digits for the doubles).
std::string formatCsvRow(const BenchRow& row);

// The value of `key` in a settings string ("spp=16 gather=64" -> "16" for "spp"), or "".
std::string settingValue(const std::string& settings, const std::string& key);
// The settings without the `key=value` pair: what distinguishes one setting of a mode from
// another across the budget ladder ("spp=4 gather=64" without spp -> "gather=64").
std::string settingsWithout(const std::string& settings, const std::string& key);

// Appends rows to a results file; writes the header first if the file is new or empty. Every
// row is flushed at once. Throws InputError if the file cannot be opened or written.
// The file is opened (and, with truncate, emptied) at the first row, not before: a run that
// fails before it has a result leaves an earlier results.csv as it was.
class ResultsCsvWriter {
public:
    explicit ResultsCsvWriter(const std::string& path, bool truncate);
    void append(const BenchRow& row);

private:
    void open();
    std::string m_path;
    bool m_truncate;
    std::ofstream m_out;
};

// Reads a results file written by ResultsCsvWriter or a peer script. Columns are found by
// header name in any order (extra columns ignored); a missing column, a row with the wrong
// number of fields or a number that does not parse is an InputError naming file and line.
std::vector<BenchRow> readResultsCsv(const std::string& path);
std::vector<BenchRow> parseResultsCsv(const std::string& text, const std::string& path);

} // namespace rayproc::bench
