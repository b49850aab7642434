// libFuzzer target: validateMesh on arbitrary triangle soups (fuzz_validate), and the physics
// solid made from them with the basins of its openings (fuzz_repair: PLIMSOLL_FUZZ_REPAIR; the
// fuzz build has no CGAL, so its caps are left to the sanitized test suite). The bytes become a
// mesh: a header (vertex count, UV mode), raw doubles for positions and UVs (so NaN, Inf, denormals
// and 1e308 all occur), then triangles of vertex indices that may repeat or point past the
// last vertex.
#include "plimsoll/geometry/validate.h"
#ifdef PLIMSOLL_FUZZ_REPAIR
#include "plimsoll/repair/physics_solid.h"
#endif

#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace {

struct Reader {
    const std::uint8_t* data;
    std::size_t size;
    bool empty() const { return size == 0; }
    template <class T>
    T take() {
        T value{};
        const std::size_t n = size < sizeof(T) ? size : sizeof(T);
        std::memcpy(&value, data, n);
        data += n;
        size -= n;
        return value;
    }
};

// Coordinates: mostly small integers (so that closed, welded, overlapping shapes occur), and
// raw doubles when the selector byte says so.
double coordinate(Reader& in) {
    const std::uint8_t kind = in.take<std::uint8_t>();
    if (kind < 0xC0) return static_cast<double>(static_cast<int>(kind % 8) - 2) * 0.5;
    return in.take<double>();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Reader in{data, size};
    plimsoll::TriangleMesh mesh;
    mesh.source = "soup";
    const std::size_t vertices = in.take<std::uint8_t>() % 64;
    // 0: no UVs, 1: one per vertex, 2: a wrong count of UVs.
    const int uvMode = in.take<std::uint8_t>() % 3;
    for (std::size_t v = 0; v < vertices; ++v) {
        const double x = coordinate(in), y = coordinate(in), z = coordinate(in);
        mesh.positions.emplace_back(x, y, z);
    }
    const std::size_t uvCount = uvMode == 0 ? 0 : uvMode == 1 ? vertices : vertices / 2 + 1;
    for (std::size_t v = 0; v < uvCount; ++v) {
        const double u = coordinate(in), w = coordinate(in);
        mesh.uvs.emplace_back(u, w);
    }
    while (!in.empty() && mesh.triangles.size() < 256) {
        plimsoll::Triangle t;
        for (std::uint32_t& index : t) {
            const std::uint8_t raw = in.take<std::uint8_t>();
            // Mostly valid indices; 0xF0 and above a whole 32-bit index, usually far out of range.
            index = raw < 0xF0 || vertices == 0 ? (vertices ? raw % vertices : raw)
                                                : in.take<std::uint32_t>();
        }
        mesh.triangles.push_back(t);
    }
    const plimsoll::ValidationReport report = plimsoll::validateMesh(mesh);
    (void)report.format();
    (void)report.closedSolid();
#ifdef PLIMSOLL_FUZZ_REPAIR
    // Every index in range (validateMesh reports the others; the repair takes valid meshes).
    if (!report.has(plimsoll::ProblemKind::IndexOutOfRange)) {
        // The fuzz build has no CGAL: a closed soup comes back as it is, and its basins are
        // looked for here (with CGAL, physicsSolidFor looks for them itself and caps them).
        plimsoll::Result<plimsoll::PhysicsSolid> solid = plimsoll::physicsSolidFor(mesh, report);
        if (solid) {
            (void)plimsoll::describeRepairs(solid->repairs);
            (void)plimsoll::findBasins(solid->mesh, solid->materialVolume);
        }
    }
#endif
    return 0;
}
