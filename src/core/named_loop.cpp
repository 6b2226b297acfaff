#include "core/named_loop.h"

namespace rayproc {

namespace {
thread_local LoopLog* t_log = nullptr;
thread_local int t_depth = 0; // named loops running on this thread
} // namespace

LoopLog::Scope::Scope(LoopLog* log) : m_previous(t_log) {
    t_log = log;
}

LoopLog::Scope::~Scope() {
    t_log = m_previous;
}

LoopLog* LoopLog::enter() {
    return t_depth++ == 0 ? t_log : nullptr;
}

void LoopLog::leave() {
    --t_depth;
}

} // namespace rayproc
