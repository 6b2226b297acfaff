#include "scene/pbrt/deferred_loads.h"

namespace rayproc::pbrt {

DeferredLoads::~DeferredLoads() {
    if (m_group) m_group->wait(); // the reads catch their own exceptions: nothing is thrown
}

void DeferredLoads::start(std::function<void(Warnings&)> read) {
    if (!m_group) m_group = std::make_unique<tbb::task_group>();
    Read& r = m_reads.emplace_back();
    r.run = std::move(read);
    m_group->run([&r] {
        try {
            r.run(r.warnings);
        } catch (...) {
            r.error = std::current_exception();
        }
    });
}

void DeferredLoads::join(Warnings& into) {
    if (!pending()) return;
    m_group->wait();
    // After a failed read the load is over: the reads after it are directives a sequential
    // load would never have reached.
    while (!m_failed && m_joined < m_reads.size()) {
        Read& r = m_reads[m_joined++];
        into.merge(r.warnings);
        if (r.error) {
            m_failed = true;
            std::rethrow_exception(r.error);
        }
    }
    m_joined = m_reads.size();
}

} // namespace rayproc::pbrt
