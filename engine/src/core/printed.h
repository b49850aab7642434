// printf-style formatting into a std::string, for the one-line messages the engine reports.
#pragma once

#include <algorithm>
#include <cstdio>
#include <string>

namespace plimsoll {

template <class... Args>
std::string printed(const char* format, Args... args) {
    const int length = std::snprintf(nullptr, 0, format, args...);
    std::string text(static_cast<std::size_t>(std::max(length, 0)), '\0');
    std::snprintf(text.data(), text.size() + 1, format, args...);
    return text;
}

}  // namespace plimsoll
