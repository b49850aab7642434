// The bench tables' cells and columns, and their output folder (bench.h).
#include "cli/bench.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace plimsoll::cli {

bool createOutputFolder(const std::string& out) {
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) std::cerr << "error: " << out << ": cannot create folder: " << ec.message() << "\n";
    return !ec;
}

std::string format(const char* spec, double value) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, spec, value);
    return buffer;
}

void printAligned(const std::vector<std::vector<std::string>>& lines, std::size_t names) {
    std::vector<std::size_t> width;
    for (const auto& line : lines) {
        width.resize(std::max(width.size(), line.size()), 0);
        for (std::size_t c = 0; c < line.size(); ++c) width[c] = std::max(width[c], line[c].size());
    }
    for (const auto& line : lines) {
        std::string text;
        for (std::size_t c = 0; c < line.size(); ++c) {
            const std::string pad(width[c] - line[c].size(), ' ');
            text += c < names ? line[c] + pad : pad + line[c];
            if (c + 1 < line.size()) text += "  ";
        }
        while (!text.empty() && text.back() == ' ') text.pop_back();
        std::cout << text << "\n";
    }
}

}  // namespace plimsoll::cli
