// A buffer whose resize leaves its new elements unwritten, for arrays a parallel loop fills in
// full right after: the kernel's first-touch page faults then fall on the loop's threads, not on
// one thread zero-filling megabytes the loop overwrites (issue 35: a texture's 9.5 MB of texels
// took 4 ms of a serial memset in the classroom's load).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace rayproc {

// std::allocator, but a value-initialising construct() (what resize(n) and vector(n) call)
// default-initialises: nothing for trivial types. Constructors with arguments are unchanged.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

// Floats that resize() leaves unwritten: every element must be written before it is read.
using UninitializedFloats = std::vector<float, DefaultInitAllocator<float>>;

} // namespace rayproc
