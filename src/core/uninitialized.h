// A buffer whose resize leaves its new elements unwritten, for arrays a parallel loop fills in
// full right after: the kernel's first-touch page faults then fall on the loop's threads, not on
// one thread zero-filling megabytes the loop overwrites (issue 35: a texture's 9.5 MB of texels
// took 4 ms of a serial memset in the classroom's load; gi's photon lists 17 ms).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace rayproc {

// std::allocator, but the value-initialising construct() that resize(n) and vector(n) call
// constructs nothing, also for structs whose members have default values (a Vec3's zeros),
// where default-initialisation would still write every byte. Only for implicit-lifetime types,
// which begin to exist in the allocated storage without a constructor call: scalars,
// aggregates, and classes with a trivial copy constructor and destructor (std::pair of such).
// Constructors with arguments are unchanged. Every element must be written before it is read.
template <class T>
struct UnwrittenAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UnwrittenAllocator<U>;
    };
    UnwrittenAllocator() = default;
    template <class U>
    UnwrittenAllocator(const UnwrittenAllocator<U>&) noexcept {}

    template <class U>
    void construct(U*) noexcept {
        static_assert(std::is_trivially_copy_constructible_v<U> &&
                          std::is_trivially_destructible_v<U>,
                      "only for types that exist without a constructor call");
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

// A vector that resize() and vector(n) leave unwritten (UnwrittenAllocator).
template <class T>
using UnwrittenVector = std::vector<T, UnwrittenAllocator<T>>;

// Floats that resize() leaves unwritten.
using UninitializedFloats = UnwrittenVector<float>;

} // namespace rayproc
