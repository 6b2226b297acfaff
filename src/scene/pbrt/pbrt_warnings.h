// Everything a pbrt scene asks for that rayproc does not do is reported once, where it first
// occurs, as "file:line: warning: what; the fallback" (with a count when it recurs), and the
// load goes on with the documented fallback (docs/pbrt-import.md).
#pragma once

#include "scene/pbrt/pbrt_tokenizer.h"

#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

namespace rayproc::pbrt {

class Warnings {
public:
    // Repeated messages are counted, not repeated.
    void add(const SourceLoc& loc, const std::string& message);
    // Another list's entries, as if each had been added here in its order (with its count).
    void merge(const Warnings& other);
    // Called at the start of every add() (not of merge()): the scene's deferred file reads
    // merge their warnings first, so the list keeps directive order (DeferredLoads).
    void setBeforeAdd(std::function<void()> hook) { m_beforeAdd = std::move(hook); }
    // "file:line: warning: message", in order of first occurrence.
    std::vector<std::string> lines() const;

private:
    struct Entry {
        std::string where;
        std::string message;
        std::size_t count = 0;
    };
    std::vector<Entry> m_entries;
    std::unordered_map<std::string, std::size_t> m_index;
    std::function<void()> m_beforeAdd;
};

} // namespace rayproc::pbrt
