// Which reader a mesh file gets: by its content first, its name second, and only the formats
// users need (OBJ, PLY, STL, FBX, glTF, GLB). Assimp picks a reader by the name and, failing
// that, by trying its readers on the bytes; its other readers (3MF, AC3D, ASE, assbin,
// COLLADA, MD5, NFF, OFF, OpenGEX, SMD, X, X3D, ...) crash, abort, hang or allocate gigabytes
// on small mutated files, so every other format is refused here, by name, before assimp runs.
#include "io/mesh_header_check.h"

#include <algorithm>
#include <array>
#include <cstring>

namespace plimsoll::detail {

namespace {

bool startsWith(std::string_view bytes, std::string_view prefix) {
    return bytes.size() >= prefix.size() && bytes.substr(0, prefix.size()) == prefix;
}

/// The bytes after a UTF-8 byte-order mark and leading white space.
std::string_view trimmedStart(std::string_view bytes) {
    if (startsWith(bytes, "\xEF\xBB\xBF")) bytes.remove_prefix(3);
    while (!bytes.empty() &&
           (bytes[0] == ' ' || bytes[0] == '\t' || bytes[0] == '\r' || bytes[0] == '\n'))
        bytes.remove_prefix(1);
    return bytes;
}

bool containsNear(std::string_view bytes, std::string_view what, std::size_t within) {
    return bytes.substr(0, within).find(what) != std::string_view::npos;
}

/// A binary STL: 80 header bytes, a triangle count, 50 bytes a triangle, exactly.
bool isBinaryStl(std::string_view bytes) {
    if (bytes.size() < 84) return false;
    std::uint32_t count = 0;
    for (int i = 3; i >= 0; --i) count = count << 8 | static_cast<unsigned char>(bytes[80 + i]);
    return bytes.size() == 84 + 50ull * count;
}

/// Text of OBJ's statements: the first statements of the file are OBJ keywords, and a
/// vertex line ("v x y z") is among the first lines with content.
bool looksLikeObj(std::string_view bytes) {
    const std::string_view head = bytes.substr(0, 1 << 16);
    if (head.find('\0') != std::string_view::npos) return false;
    static const std::array<std::string_view, 16> keywords{
        "v", "vt", "vn",     "vp",     "f", "l",    "p",    "o",
        "g", "s",  "usemtl", "mtllib", "#", "curv", "surf", "cstype"};
    bool vertex = false;
    int statements = 0;
    std::size_t at = 0;
    while (at < head.size() && statements < 64) {
        std::size_t end = head.find('\n', at);
        if (end == std::string_view::npos) end = head.size();
        std::string_view line = trimmedStart(head.substr(at, end - at));
        at = end + 1;
        if (line.empty()) continue;
        const std::string_view word =
            line.substr(0, std::min(line.find_first_of(" \t\r"), line.size()));
        if (word.front() == '#') continue;
        if (std::find(keywords.begin(), keywords.end(), word) == keywords.end()) return false;
        vertex = vertex || word == "v";
        ++statements;
    }
    return vertex;
}

/// The content's format among the allowed ones, else empty.
std::string allowedByContent(std::string_view bytes) {
    if (startsWith(bytes, "glTF")) return "glb";
    if (startsWith(bytes, "ply\n") || startsWith(bytes, "ply\r\n")) return "ply";
    if (startsWith(bytes, "Kaydara FBX Binary")) return "fbx";  // all assimp compares
    const std::string_view text = trimmedStart(bytes);
    if (startsWith(text, "; FBX") ||
        (startsWith(text, ";") && containsNear(bytes, "FBXHeaderExtension", 4096)))
        return "fbx";
    if (startsWith(text, "FBXHeaderExtension:")) return "fbx";
    if (startsWith(text, "{") && containsNear(bytes, "\"asset\"", 1 << 20)) return "gltf";
    if (isBinaryStl(bytes)) return "stl";
    if (startsWith(text, "solid") && containsNear(bytes, "facet", 4096)) return "stl";
    if (looksLikeObj(bytes)) return "obj";
    return {};
}

/// What a refused file is, by its content, for the message; empty when not recognised.
std::string refusedByContent(std::string_view bytes) {
    const std::string_view text = trimmedStart(bytes);
    if (startsWith(text, "<?xml") || startsWith(text, "<")) {
        if (containsNear(bytes, "<COLLADA", 4096)) return "COLLADA";
        if (containsNear(bytes, "<X3D", 4096)) return "X3D";
        return "XML";
    }
    if (startsWith(bytes, "PK\x03\x04")) return "a ZIP archive (3MF, AMF or a zipped model)";
    if (startsWith(bytes, "xof ")) return "DirectX X";
    if (startsWith(bytes, "ASSIMP.binary-dump")) return "assimp binary (assbin)";
    if (startsWith(bytes, "BLENDER")) return "Blender";
    if (startsWith(bytes, "AC3D")) return "AC3D";
    if (startsWith(text, "*3DSMAX_ASCIIEXPORT")) return "3ds Max ASCII (ASE)";
    if (startsWith(text, "MD5Version")) return "MD5";
    if (startsWith(text, "OFF") || startsWith(text, "COFF") || startsWith(text, "NOFF"))
        return "OFF";
    if (startsWith(text, "version 1") && containsNear(bytes, "nodes", 256)) return "Valve SMD";
    if (startsWith(text, "Metric") || containsNear(bytes, "GeometryNode", 4096)) return "OpenGEX";
    if (startsWith(bytes, "MM") && bytes.size() > 6) return "3DS";
    if (startsWith(bytes, "IDP2") || startsWith(bytes, "IDP3")) return "Quake MD2/MD3";
    return {};
}

bool allowedName(const std::string& format) {
    static const std::array<std::string_view, 6> names{"obj", "ply", "stl", "fbx", "gltf", "glb"};
    return std::find(names.begin(), names.end(), format) != names.end();
}

}  // namespace

Result<std::string> meshFormat(std::string_view bytes, const std::string& format,
                               const std::string& file) {
    const std::string content = allowedByContent(bytes);
    if (!content.empty()) return content;  // the content decides, whatever the name says
    const std::string refused = refusedByContent(bytes);
    const std::string allowed = "Plimsoll reads OBJ, PLY, STL, FBX, glTF and GLB meshes only";
    if (!refused.empty())
        return makeError(ErrorKind::format,
                         file + ": is a " + refused + " file (by its content): " + allowed);
    // Unrecognised content named .obj goes to the OBJ checks, which keep only the statements
    // they understand (assimp never sees the file itself). Every other allowed format is
    // recognised by its content or not read: assimp, given a name whose reader declines the
    // bytes, would try its other readers on them.
    if (format == "obj") return format;
    // A binary STL's 80-byte header is free text: one whose count disagrees with its size is
    // still an STL, refused by the STL checks with what is wrong (the count against the limit,
    // the size against the count).
    if (format == "stl" && bytes.size() >= 84) return format;
    if (allowedName(format))
        return makeError(ErrorKind::format, file + ": named ." + format +
                                                " but its content is not " +
                                                "that format's (by its first bytes)");
    return makeError(ErrorKind::format,
                     file + ": " +
                         (format.empty() ? std::string("no extension") : "\"." + format + "\"") +
                         " and content of no allowed format: " + allowed);
}

}  // namespace plimsoll::detail
