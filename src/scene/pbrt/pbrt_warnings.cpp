#include "scene/pbrt/pbrt_warnings.h"

namespace rayproc::pbrt {

void Warnings::add(const SourceLoc& loc, const std::string& message) {
    if (m_beforeAdd) m_beforeAdd();
    auto [it, inserted] = m_index.emplace(message, m_entries.size());
    if (inserted) m_entries.push_back({loc.fileAndLine(), message, 0});
    ++m_entries[it->second].count;
}

void Warnings::merge(const Warnings& other) {
    for (const Entry& e : other.m_entries) {
        auto [it, inserted] = m_index.emplace(e.message, m_entries.size());
        if (inserted) m_entries.push_back({e.where, e.message, 0});
        m_entries[it->second].count += e.count;
    }
}

std::vector<std::string> Warnings::lines() const {
    std::vector<std::string> out;
    for (const Entry& e : m_entries) {
        std::string line = e.where + ": warning: " + e.message;
        if (e.count > 1) line += " (" + std::to_string(e.count) + " times; the first is shown)";
        out.push_back(line);
    }
    return out;
}

} // namespace rayproc::pbrt
