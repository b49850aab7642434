#include "plimsoll/io/file_util.h"
#include "plimsoll/io/mesh_io.h"

#include <charconv>
#include <string>

namespace plimsoll {

namespace {

/// Appends " " and x with 17 significant digits, as printf("%.17g") in the C locale: enough to
/// read back the same double, and independent of the process locale (a GUI may set LC_NUMERIC
/// to one with a decimal comma), so the same mesh always gives the same bytes.
void appendNumber(std::string& line, double x) {
    char buffer[32];
    // 32 characters hold any double at 17 digits ("-1.2345678901234567e-308" is 24).
    char* end =
        std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 17).ptr;
    line += ' ';
    line.append(buffer, end);
}

}  // namespace

Status writeObj(const TriangleMesh& mesh, const std::filesystem::path& path) {
    // One v (and one vt) per vertex, no deduplication: vertex i is v/vt i + 1, so a reader
    // that joins identical vertices rebuilds exactly this mesh.
    const bool withUvs = mesh.hasUvs();
    return writeFileAtomically(path, [&](std::ostream& out) {
        std::string line;
        out << "# written by Plimsoll\n";
        for (const Eigen::Vector3d& p : mesh.positions) {
            line = "v";
            for (int k = 0; k < 3; ++k) appendNumber(line, p[k]);
            line += '\n';
            out << line;
        }
        if (withUvs) {
            for (const Eigen::Vector2d& uv : mesh.uvs) {
                line = "vt";
                appendNumber(line, uv.x());
                appendNumber(line, uv.y());
                line += '\n';
                out << line;
            }
        }
        for (const Triangle& t : mesh.triangles) {
            line = "f";
            for (std::uint32_t index : t) {
                const std::string i = std::to_string(index + 1);
                line += ' ';
                line += i;
                if (withUvs) {
                    line += '/';
                    line += i;
                }
            }
            line += '\n';
            out << line;
        }
        return static_cast<bool>(out);
    });
}

}  // namespace plimsoll
