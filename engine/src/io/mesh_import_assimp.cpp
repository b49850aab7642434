// assimp adapter: the only file that includes assimp. Everything downstream sees TriangleMesh.
#include "plimsoll/io/mesh_io.h"

#include "io/mesh_header_check.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll_runtime/runtime.hpp"

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

namespace plimsoll {

namespace fs = std::filesystem;

namespace {

/// A file's bytes, for assimp to read (shared with the checks that read them first).
class BytesStream : public Assimp::IOStream {
public:
    explicit BytesStream(std::shared_ptr<const std::string> bytes) : bytes_(std::move(bytes)) {}
    size_t Read(void* buffer, size_t size, size_t count) override {
        if (size == 0) return 0;
        const size_t items = std::min(count, (bytes_->size() - at_) / size);
        std::memcpy(buffer, bytes_->data() + at_, items * size);
        at_ += items * size;
        return items;
    }
    size_t Write(const void*, size_t, size_t) override { return 0; }
    aiReturn Seek(size_t offset, aiOrigin origin) override {
        const size_t base = origin == aiOrigin_SET   ? 0
                            : origin == aiOrigin_CUR ? at_
                                                     : bytes_->size();
        if (offset > bytes_->size() - base) return aiReturn_FAILURE;
        at_ = base + offset;
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return at_; }
    size_t FileSize() const override { return bytes_->size(); }
    void Flush() override {}

private:
    std::shared_ptr<const std::string> bytes_;
    size_t at_ = 0;
};

/// Every file assimp opens besides the mesh itself (glTF buffers, an OBJ's materials) goes
/// through here: only inside the mesh's folder (a buffer URI "../../x" or "/dev/zero" is
/// refused), only regular files, at most kMaxMeshFileBytes, read-only. Without a folder (a mesh
/// from memory) nothing is opened. The first refusal is kept for the error message, since
/// assimp's own says only "could not open". Each file is read once (`load`): the checks before
/// assimp and assimp itself see the same bytes, even if the file is replaced in between.
class ConfinedFileSystem : public Assimp::IOSystem {
public:
    ConfinedFileSystem(std::optional<fs::path> folder, std::string mesh)
        : folder_(std::move(folder)), mesh_(std::move(mesh)) {}

    bool Exists(const char* file) const override {
        const Result<fs::path> path = resolve(file);
        return path && checkRegularFile(*path).ok();
    }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (mode && std::strpbrk(mode, "wa+")) return refuse(file, "assimp asked to write it");
        Result<std::shared_ptr<const std::string>> bytes = load(file);
        if (!bytes) return remember(bytes.error().message);
        return new BytesStream(std::move(bytes).value());
    }

    /// The bytes of the file `file` names, read the first time it is asked for.
    Result<std::shared_ptr<const std::string>> load(const std::string& file) {
        Result<fs::path> path = resolve(file.c_str());
        if (!path) return path.error();
        const auto known = read_.find(path->string());
        if (known != read_.end()) return known->second;
        // Opened as the runtime opens a bundle's files: component by component from the
        // folder's descriptor, never through a link, so nothing swapped in after the check
        // above is followed out of the folder.
        std::string bytes;
        std::string error;
        plimsoll_runtime::FileReadProblem problem{};
        if (!plimsoll_runtime::readFileInside(folder_->string(),
                                              fs::path(file).lexically_normal().generic_string(),
                                              kMaxMeshFileBytes, bytes, error, &problem)) {
            const bool tooLarge = problem == plimsoll_runtime::FileReadProblem::TooLarge;
            return makeError(tooLarge ? ErrorKind::limit : ErrorKind::io,
                             mesh_ + ": a file it refers to: " + error +
                                 (tooLarge ? " (kMaxMeshFileBytes)" : ""));
        }
        auto shared = std::make_shared<const std::string>(std::move(bytes));
        read_.emplace(path->string(), shared);
        return shared;
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }

    const std::string& refusal() const { return refusal_; }
    bool hasFolder() const { return folder_.has_value(); }

private:
    Result<fs::path> resolve(const char* file) const {
        if (!folder_)
            return makeError(ErrorKind::io, mesh_ + ": refers to \"" + std::string(file) +
                                                "\", which is not read from memory");
        return pathInside(*folder_, file, mesh_ + ": a file it refers to");
    }
    Assimp::IOStream* refuse(const char* file, const std::string& why) {
        return remember(mesh_ + ": \"" + std::string(file) + "\": " + why);
    }
    Assimp::IOStream* remember(const std::string& message) {
        if (refusal_.empty()) refusal_ = message;
        return nullptr;
    }

    std::optional<fs::path> folder_;
    std::string mesh_;
    std::string refusal_;
    std::map<std::string, std::shared_ptr<const std::string>> read_;
};

void configure(Assimp::Importer& importer) {
    // Points and lines carry no surface: drop them instead of failing on mixed files.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // Plimsoll reads shapes: an FBX's cameras and lights are not converted (its animations are
    // hidden from assimp by the check, which assimp's setting for them does not do: checkFbx).
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
}

unsigned importFlags(MeshLoadOptions options) {
    // No normal generation, no degenerate removal, no vertex welding beyond exact duplicates
    // (and none at all for the frames of a deforming mesh): validation must see the file as it
    // is.
    unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;
    if (options.joinIdenticalVertices) flags |= aiProcess_JoinIdenticalVertices;
    return flags;
}

/// A number of the scene's metadata (assimp stores FBX settings as double, float or int).
std::optional<double> metadataNumber(const aiScene* scene, const char* key) {
    const aiMetadata* data = scene->mMetaData;
    if (!data) return std::nullopt;
    for (unsigned k = 0; k < data->mNumProperties; ++k) {
        if (std::strcmp(data->mKeys[k].C_Str(), key) != 0 || !data->mValues[k].mData) continue;
        const aiMetadataEntry& value = data->mValues[k];
        switch (value.mType) {
            case AI_DOUBLE:
                return *static_cast<const double*>(value.mData);
            case AI_FLOAT:
                return *static_cast<const float*>(value.mData);
            case AI_INT32:
                return *static_cast<const std::int32_t*>(value.mData);
            default:
                return std::nullopt;
        }
    }
    return std::nullopt;
}

std::string metadataString(const aiScene* scene, const char* key) {
    const aiMetadata* data = scene->mMetaData;
    if (!data) return {};
    for (unsigned k = 0; k < data->mNumProperties; ++k) {
        const aiMetadataEntry& value = data->mValues[k];
        if (std::strcmp(data->mKeys[k].C_Str(), key) == 0 && value.mType == AI_AISTRING &&
            value.mData)
            return static_cast<const aiString*>(value.mData)->C_Str();
    }
    return {};
}

/// Metres per file unit and where that comes from. FBX gives UnitScaleFactor in centimetres
/// per unit (1: centimetres, 100: metres), which assimp leaves unapplied; glTF is metres by
/// its specification; assimp's COLLADA reader applies the file's <unit> itself; OBJ, STL and
/// PLY carry no unit.
Result<std::pair<double, std::string>> fileUnit(const aiScene* scene, const std::string& name,
                                                MeshLoadOptions options) {
    if (options.unitScale > 0) return std::pair{options.unitScale, std::string("set by the user")};
    const std::string format = metadataString(scene, "SourceAsset_Format");
    if (format.find("FBX") != std::string::npos) {
        const std::optional<double> factor = metadataNumber(scene, "UnitScaleFactor");
        if (!factor)
            return std::pair{0.01, std::string("FBX without UnitScaleFactor: centimetres")};
        if (!std::isfinite(*factor) || *factor <= 0 || *factor > 1e8)
            return makeError(ErrorKind::format,
                             name + ": FBX UnitScaleFactor " + std::to_string(*factor) +
                                 " is not a usable length unit (centimetres per unit)");
        std::ostringstream source;
        source << "FBX UnitScaleFactor " << *factor;
        return std::pair{*factor / 100.0, source.str()};
    }
    if (format.find("glTF") != std::string::npos)
        return std::pair{1.0, std::string("glTF (metres)")};
    if (format.find("Collada") != std::string::npos || format.find("COLLADA") != std::string::npos)
        return std::pair{1.0, std::string("COLLADA <unit>, applied by the reader")};
    return std::pair{1.0, std::string("no unit in the file: metres")};
}

Result<TriangleMesh> fromScene(const aiScene* scene, const Assimp::Importer& importer,
                               const std::string& name, MeshLoadOptions options,
                               MeshFileFacts* facts, const std::string& refusal = {}) {
    if (!scene || !scene->mRootNode) {
        if (!refusal.empty()) return makeError(ErrorKind::io, refusal);
        return makeError(ErrorKind::format,
                         name + ": cannot read mesh: " + importer.GetErrorString());
    }

    // Formats without a count in a header (OBJ, glTF) are counted once read, before copying.
    std::uint64_t triangles = 0, vertices = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        triangles += scene->mMeshes[m]->mNumFaces;
        vertices += scene->mMeshes[m]->mNumVertices;
    }
    if (triangles > kMaxTriangles || vertices > kMaxVertices) {
        return makeError(
            ErrorKind::limit,
            name + ": " + std::to_string(triangles) + " triangles, " + std::to_string(vertices) +
                " vertices: more than the limit " +
                (triangles > kMaxTriangles ? "kMaxTriangles = " + std::to_string(kMaxTriangles)
                                           : "kMaxVertices = " + std::to_string(kMaxVertices)) +
                " (limits.h)");
    }
    Result<std::pair<double, std::string>> unit = fileUnit(scene, name, options);
    if (!unit) return unit.error();

    TriangleMesh mesh;
    mesh.source = name;
    // UVs are kept per part: a part without them gets (0, 0) at its corners rather than
    // dropping the UVs of every other part.
    bool anyUvs = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        if (part->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)
            anyUvs = anyUvs || part->HasTextureCoords(0);
    }

    MeshFileFacts found;
    found.unitScale = unit->first;
    found.unitSource = unit->second;
    const double scale = unit->first;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        if (!(part->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        const bool partUvs = part->HasTextureCoords(0);
        for (unsigned v = 0; v < part->mNumVertices; ++v) {
            const aiVector3D& p = part->mVertices[v];
            // Exactly the file's numbers when no unit applies (bakes stay byte-identical).
            if (scale == 1.0)
                mesh.positions.emplace_back(p.x, p.y, p.z);
            else
                mesh.positions.emplace_back(scale * double(p.x), scale * double(p.y),
                                            scale * double(p.z));
            if (anyUvs) {
                const aiVector3D t = partUvs ? part->mTextureCoords[0][v] : aiVector3D(0, 0, 0);
                mesh.uvs.emplace_back(t.x, t.y);
            }
        }
        MeshPart record{part->mName.C_Str(), mesh.triangles.size(), 0, partUvs};
        for (unsigned f = 0; f < part->mNumFaces; ++f) {
            const aiFace& face = part->mFaces[f];
            if (face.mNumIndices != 3) continue;
            mesh.triangles.push_back(
                {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
        record.triangleCount = mesh.triangles.size() - record.firstTriangle;
        if (record.triangleCount > 0) found.parts.push_back(std::move(record));
    }
    if (mesh.triangles.empty())
        return makeError(ErrorKind::format, name + ": the file holds no triangles");
    if (facts) *facts = std::move(found);
    return mesh;
}

/// An OBJ's text through detail::objGeometry (v / vt / vn / f only, every index checked), and
/// only that checked geometry through assimp: its OBJ reader crashes on what the check refuses.
Result<TriangleMesh> loadObj(std::istream& text, const std::string& source, MeshLoadOptions options,
                             MeshFileFacts* facts) {
    Result<std::string> geometry = detail::objGeometry(text, source);
    if (!geometry) return geometry.error();
    if (geometry->empty())
        return makeError(ErrorKind::format, source + ": no triangles (no v or f lines)");
    Assimp::Importer importer;
    configure(importer);
    const aiScene* scene = importer.ReadFileFromMemory(geometry->data(), geometry->size(),
                                                       importFlags(options), "obj");
    return fromScene(scene, importer, source, options, facts);
}

/// A PLY file through detail::plyGeometry, and only the canonical PLY it writes through assimp.
Result<TriangleMesh> loadPly(std::string_view bytes, const std::string& source,
                             MeshLoadOptions options, MeshFileFacts* facts) {
    Result<std::string> geometry = detail::plyGeometry(bytes, source);
    if (!geometry) return geometry.error();
    Assimp::Importer importer;
    configure(importer);
    const aiScene* scene = importer.ReadFileFromMemory(geometry->data(), geometry->size(),
                                                       importFlags(options), "ply");
    return fromScene(scene, importer, source, options, facts);
}

/// A mesh file's bytes through the checks assimp needs and then assimp; `folder` is where the
/// files it refers to may be read from (none for a mesh from memory).
Result<TriangleMesh> importBytes(std::string_view bytes, std::string format,
                                 const std::string& source, std::optional<fs::path> folder,
                                 MeshLoadOptions options, MeshFileFacts* facts) {
    for (char& c : format) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (bytes.empty()) return makeError(ErrorKind::format, source + ": empty file");
    // Allowed formats only, chosen by content: nothing else reaches assimp.
    Result<std::string> allowed = detail::meshFormat(bytes, format, source);
    if (!allowed) return allowed.error();
    format = *allowed;
    if (format == "obj") {
        std::istringstream text{std::string(bytes)};
        return loadObj(text, source, options, facts);
    }
    if (detail::isPly(bytes, format)) return loadPly(bytes, source, options, facts);
    Assimp::Importer importer;
    configure(importer);
    auto* files = new ConfinedFileSystem(std::move(folder), source);
    importer.SetIOHandler(files);  // the importer owns it
    // A glTF's external buffers are read for the checks through the same file system, and
    // only from a mesh read from a folder.
    detail::ReadReferencedFile readReferenced;
    if (files->hasFolder())
        readReferenced = [files](const std::string& uri) { return files->load(uri); };
    std::string forAssimp;
    if (Status checked = detail::checkMeshBytes(bytes, source, format, readReferenced, &forAssimp);
        !checked.ok())
        return checked.error();
    const std::string_view given = forAssimp.empty() ? bytes : std::string_view(forAssimp);
    const aiScene* scene = importer.ReadFileFromMemory(given.data(), given.size(),
                                                       importFlags(options), format.c_str());
    return fromScene(scene, importer, source, options, facts, files->refusal());
}

}  // namespace

Result<TriangleMesh> loadMesh(const fs::path& path, MeshLoadOptions options, MeshFileFacts* facts) {
    Result<std::string> bytes = readWholeFile(path, kMaxMeshFileBytes, "kMaxMeshFileBytes");
    if (!bytes) {
        if (bytes.error().message.ends_with("is a folder, not a file"))
            return makeError(ErrorKind::io, path.string() + ": is a folder, not a mesh file");
        return bytes.error();
    }
    std::string extension = path.extension().string();
    if (!extension.empty()) extension.erase(0, 1);
    fs::path folder = path.parent_path();
    if (folder.empty()) folder = ".";
    return importBytes(*bytes, extension, path.string(), folder, options, facts);
}

Result<TriangleMesh> loadMeshFromMemory(std::string_view bytes, const std::string& format,
                                        const std::string& source, MeshLoadOptions options,
                                        MeshFileFacts* facts) {
    return importBytes(bytes, format, source, std::nullopt, options, facts);
}

bool MeshFileFacts::someUvsMissing() const {
    bool with = false, without = false;
    for (const MeshPart& part : parts) (part.hasUvs ? with : without) = true;
    return with && without;
}

std::optional<double> parseLengthUnit(const std::string& text) {
    static const std::pair<const char*, double> kNames[] = {
        {"m", 1.0},     {"cm", 0.01},   {"mm", 0.001}, {"km", 1000.0},
        {"in", 0.0254}, {"ft", 0.3048}, {"yd", 0.9144}};
    for (const auto& [unit, metres] : kNames)
        if (text == unit) return metres;
    if (text.empty()) return std::nullopt;
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || !std::isfinite(value) || value <= 0)
        return std::nullopt;
    return value;
}

std::string lengthUnitName(double metresPerUnit) {
    static const std::pair<double, const char*> kNames[] = {
        {1.0, "metres"},    {0.01, "centimetres"}, {0.001, "millimetres"}, {1000.0, "kilometres"},
        {0.0254, "inches"}, {0.3048, "feet"},      {0.9144, "yards"}};
    for (const auto& [metres, name] : kNames)
        if (std::abs(metresPerUnit - metres) <= 1e-12 * metres) return name;
    std::ostringstream text;
    text << metresPerUnit << " m";
    return text.str();
}

}  // namespace plimsoll
