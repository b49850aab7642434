// Plain values as bytes, for the snapshots of Body, WaterGraph, RadiationMemory and Simulation:
// native byte order and IEEE doubles (a snapshot is restored by the same build it came from or
// one of the same platform; docs/c-abi.md, "Determinism").
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace plimsoll_runtime {

template <class T>
void putBytes(std::vector<std::uint8_t>& out, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &value, sizeof(T));
}

/// Reads a T at `at` and advances it; false (nothing read) past the end.
template <class T>
bool takeBytes(const std::vector<std::uint8_t>& in, std::size_t& at, T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (in.size() < at || in.size() - at < sizeof(T)) return false;
    std::memcpy(&value, in.data() + at, sizeof(T));
    at += sizeof(T);
    return true;
}

/// FNV-1a, 64 bits: the state hash of a snapshot.
inline std::uint64_t fnv1a(const std::vector<std::uint8_t>& bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (std::uint8_t byte : bytes) {
        h ^= byte;
        h *= 0x100000001b3ull;
    }
    return h;
}

}  // namespace plimsoll_runtime
