// FNV-1a, 64 bits: the content hash of the caches (a generated atlas, radiation coefficients),
// which only need to notice that their inputs changed, not resist an adversary.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace plimsoll {

inline constexpr std::uint64_t kFnv1aBasis = 0xcbf29ce484222325ull;

/// `hash` extended by `bytes` bytes at `data`.
inline std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
        hash ^= p[i];
        hash *= 0x100000001b3ull;
    }
    return hash;
}

/// 16 lower-case hex digits.
inline std::string hashText(std::uint64_t hash) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

}  // namespace plimsoll
