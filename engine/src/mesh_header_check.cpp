// Reads the element counts that PLY and binary STL headers declare and refuses absurd ones
// before assimp sees the file: its importers reserve memory for the declared count, so a
// 100-byte file claiming 1e9 triangles would allocate tens of GB (or throw std::bad_alloc).
#include "mesh_header_check.h"

#include "plimsoll/limits.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

namespace plimsoll::detail {

namespace fs = std::filesystem;

namespace {

std::string limitError(const std::string& file, const std::string& what, std::uint64_t count,
                       const char* limitName, std::uint64_t limit) {
    return file + ": " + what + " " + std::to_string(count) + ", more than the limit " +
           limitName + " = " + std::to_string(limit) + " (limits.h)";
}

/// Smallest number of bytes one PLY property takes in a binary body (a list: its count alone).
std::uint64_t plyTypeBytes(const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "double" || type == "float64") return 8;
    return 4;  // int, uint, float and their sized names
}

Status checkPly(const std::string& file, std::ifstream& in, std::uintmax_t fileBytes) {
    // The header is text up to "end_header"; real ones are a few hundred bytes.
    constexpr std::size_t kMaxHeaderBytes = 1 << 16;
    std::string line;
    std::size_t headerBytes = 0;
    bool binary = false, ended = false;
    struct Element {
        std::string name;
        std::uint64_t count = 0;
        std::uint64_t minBytes = 0;  // per element, binary body
    };
    std::vector<Element> elements;
    while (std::getline(in, line)) {
        headerBytes += line.size() + 1;
        if (headerBytes > kMaxHeaderBytes) return makeError(file + ": PLY header longer than 64 KB");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "end_header") {
            ended = true;
            break;
        }
        if (keyword == "format") {
            std::string format;
            words >> format;
            binary = format.rfind("binary", 0) == 0;
        } else if (keyword == "element") {
            std::string name, countText;
            words >> name >> countText;
            Element e{name};
            const auto [end, ec] = std::from_chars(countText.data(),
                                                   countText.data() + countText.size(), e.count);
            if (ec != std::errc() || end != countText.data() + countText.size()) {
                return makeError(file + ": PLY header: element " + name + " has count '" +
                                 countText + "', not a number");
            }
            elements.push_back(e);
        } else if (keyword == "property" && !elements.empty()) {
            std::string type;
            words >> type;
            if (type == "list") words >> type;  // the count's type; the items may be 0
            elements.back().minBytes += plyTypeBytes(type);
        }
    }
    if (!ended) return makeError(file + ": PLY header has no end_header (truncated?)");
    std::uint64_t bodyNeeds = 0;
    for (const Element& e : elements) {
        if (e.name == "face" && e.count > kMaxTriangles)
            return makeError(limitError(file, "PLY header declares faces:", e.count,
                                        "kMaxTriangles", kMaxTriangles));
        if (e.name == "vertex" && e.count > kMaxVertices)
            return makeError(limitError(file, "PLY header declares vertices:", e.count,
                                        "kMaxVertices", kMaxVertices));
        if (e.count > kMaxVertices)  // other elements (edges, materials): as many as vertices
            return makeError(limitError(file, "PLY header declares " + e.name + " elements:",
                                        e.count, "kMaxVertices", kMaxVertices));
        // An ASCII element takes at least two bytes ("0\n"), a binary one its properties.
        bodyNeeds += e.count * (binary ? std::max<std::uint64_t>(1, e.minBytes) : 2);
    }
    if (!binary && bodyNeeds > 0) --bodyNeeds;  // the last line may lack its newline
    const std::uint64_t body = fileBytes - std::min<std::uintmax_t>(fileBytes, headerBytes);
    if (bodyNeeds > body) {
        return makeError(file + ": PLY header declares elements needing at least " +
                         std::to_string(bodyNeeds) + " bytes, the file has " +
                         std::to_string(body) + " after the header (truncated?)");
    }
    return Ok{};
}

Status checkBinaryStl(const std::string& file, std::ifstream& in, std::uintmax_t fileBytes) {
    // 80-byte header, uint32 triangle count, 50 bytes per triangle. An ASCII STL starts with
    // "solid"; a binary one may too, so a count that matches the size decides.
    char head[84] = {};
    in.read(head, sizeof head);
    if (fileBytes < 84 || !in) return Ok{};  // too short for binary: assimp reports it
    const auto* b = reinterpret_cast<const unsigned char*>(head + 80);
    const std::uint64_t count = b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint64_t(b[3]) << 24);
    const std::uint64_t needed = 84 + 50 * count;
    if (needed == fileBytes) {
        if (count > kMaxTriangles)
            return makeError(limitError(file, "binary STL holds triangles:", count,
                                        "kMaxTriangles", kMaxTriangles));
        return Ok{};
    }
    if (std::string(head, 5) == "solid") return Ok{};  // ASCII
    if (needed < fileBytes) return Ok{};  // trailing bytes: the importer decides
    if (count > kMaxTriangles)
        return makeError(limitError(file, "binary STL header declares triangles:", count,
                                    "kMaxTriangles", kMaxTriangles));
    return makeError(file + ": binary STL header declares " + std::to_string(count) +
                     " triangles (" + std::to_string(needed) + " bytes), the file has " +
                     std::to_string(fileBytes) + " bytes (truncated?)");
}

}  // namespace

Result<std::string> objGeometry(std::istream& text, const std::string& file) {
    std::string geometry;
    // Running counts of positions, texture coordinates and normals; the largest positive
    // reference to each (a positive index may name one defined further down the file).
    std::uint64_t defined[3] = {0, 0, 0};
    std::uint64_t largest[3] = {0, 0, 0};
    std::uint64_t largestLine[3] = {0, 0, 0};
    const char* const kinds[3] = {"vertex", "texture coordinate", "normal"};
    std::string line;
    std::uint64_t number = 0;
    while (std::getline(text, line)) {
        ++number;
        std::size_t at = line.find_first_not_of(" \t");
        if (at == std::string::npos) continue;
        const std::size_t end = line.find_first_of(" \t\r", at);
        const std::string keyword = line.substr(at, end == std::string::npos ? end : end - at);
        if (keyword == "v") ++defined[0];
        else if (keyword == "vt") ++defined[1];
        else if (keyword == "vn") ++defined[2];
        else if (keyword != "f") continue;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        geometry += line;
        geometry += '\n';
        if (keyword != "f") continue;
        std::istringstream refs(end == std::string::npos ? std::string() : line.substr(end));
        std::string ref;
        while (refs >> ref) {
            // "v", "v/vt", "v//vn", "v/vt/vn".
            std::size_t start = 0;
            for (int kind = 0; kind < 3 && start <= ref.size(); ++kind) {
                const std::size_t slash = std::min(ref.find('/', start), ref.size());
                const std::string part = ref.substr(start, slash - start);
                start = slash + 1;
                if (part.empty() && kind > 0) continue;
                long long index = 0;
                const auto [ptr, error] =
                    std::from_chars(part.data(), part.data() + part.size(), index);
                if (error != std::errc() || ptr != part.data() + part.size() || index == 0) {
                    return makeError(file + ": line " + std::to_string(number) + ": '" + ref +
                                     "' is not a " + kinds[kind] + " index");
                }
                if (index < 0) {
                    const std::uint64_t back = static_cast<std::uint64_t>(-(index + 1)) + 1;
                    if (back > defined[kind]) {
                        return makeError(file + ": line " + std::to_string(number) + ": " +
                                         kinds[kind] + " index out of range: " +
                                         std::to_string(index) + " (" +
                                         std::to_string(defined[kind]) + " defined before it)");
                    }
                } else if (static_cast<std::uint64_t>(index) > largest[kind]) {
                    largest[kind] = static_cast<std::uint64_t>(index);
                    largestLine[kind] = number;
                }
            }
        }
    }
    for (int kind = 0; kind < 3; ++kind) {
        if (largest[kind] > defined[kind]) {
            return makeError(file + ": line " + std::to_string(largestLine[kind]) + ": " +
                             kinds[kind] + " index out of range: " +
                             std::to_string(largest[kind]) + " (the file defines " +
                             std::to_string(defined[kind]) + ")");
        }
    }
    return geometry;
}

Status checkMeshHeader(const fs::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (ec) return Ok{};  // the importer reports unreadable files
    std::ifstream in(path, std::ios::binary);
    if (!in) return Ok{};
    char magic[4] = {};
    in.read(magic, sizeof magic);
    in.clear();
    in.seekg(0);
    if (std::string(magic, 3) == "ply" && (magic[3] == '\n' || magic[3] == '\r'))
        return checkPly(file, in, bytes);
    if (std::string(magic, 4) == "glTF") {
        // Binary glTF: magic, version, total length (little-endian uint32). Assimp answers a
        // cut-off file with "no suitable reader", which sends users looking in the wrong place.
        unsigned char header[12] = {};
        in.read(reinterpret_cast<char*>(header), sizeof header);
        const std::uint64_t length = header[8] | (header[9] << 8) | (header[10] << 16) |
                                     (std::uint64_t(header[11]) << 24);
        if (!in || length > bytes) {
            return makeError(file + ": GLB header says " + std::to_string(length) +
                             " bytes, the file has " + std::to_string(bytes) + " (truncated?)");
        }
        return Ok{};
    }
    std::string extension = path.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension == ".stl") return checkBinaryStl(file, in, bytes);
    return Ok{};
}

std::string formatBytesImpl(double bytes) {
    const char* units[] = {"bytes", "KB", "MB", "GB", "TB", "PB"};
    int unit = 0;
    while (bytes >= 1024.0 && unit < 5) {
        bytes /= 1024.0;
        ++unit;
    }
    char text[32];
    std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", bytes, units[unit]);
    return text;
}

}  // namespace plimsoll::detail

namespace plimsoll {
std::string formatBytes(double bytes) { return detail::formatBytesImpl(bytes); }
}  // namespace plimsoll
