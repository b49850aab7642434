// libFuzzer target: the runtime's bundle loader (loadBundle) on a folder of a small valid
// bundle (4 samples, a one-node water graph, a permeability map) where one file comes from the
// input. The first byte picks it: 0, the manifest text (the input itself); 1, samples.exr and
// 2, the PNG map: the valid file patched with the input (4 bytes of offset, then the bytes to
// write there; a high bit in the offset also cuts the file there), so the mutations stay near
// real files. A loaded bundle must hold only finite samples.
#include "io/exr_io.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/io/painted_map_io.h"

#include "plimsoll_runtime/runtime.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

const char* kManifest =
    R"({"format": "plimsoll-runtime-bundle", "schema_version": 1, "schema_minor": 1,
 "files": [], "texture_size": 16, "texel_samples": 4,
 "uv_placement": {"scale": 1, "offset": [0, 0]},
 "mass_properties": {"texture": {"mass": 1, "volume": 0.001, "center_of_mass": [0, 0, 0],
                                 "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}},
 "water_graph": {"path": "graph.json", "permeability": 0.5},
 "painted_maps": {"permeability": {"path": "perm.png"}}})";
const char* kGraph =
    R"({"schema_version": 1, "nodes": [{"id": "a", "position": [0, 0, 0], "capacity": 1}], "pipes": []})";

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}
void writeAll(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

struct Bundle {
    std::string folder, exr, png;
};

const Bundle& bundle() {
    static const Bundle b = [] {
        Bundle made;
        char pattern[] = "/tmp/plimsoll-fuzz-bundle-XXXXXX";
        if (!::mkdtemp(pattern)) std::abort();
        made.folder = pattern;
        plimsoll::detail::FloatImage samples;
        samples.width = 4;
        samples.height = 1;
        samples.channels = {"x", "y", "px", "py", "pz", "ax", "ay", "az", "area", "coverage"};
        for (int i = 0; i < 4; ++i) {
            const float row[10] = {float(i), 3, 0.1f * i, -0.1f, 0, 0, -0.01f, 0, 0.01f, 1};
            samples.pixels.insert(samples.pixels.end(), row, row + 10);
        }
        if (!plimsoll::detail::writeExr(made.folder + "/samples.exr", samples).ok()) std::abort();
        made.exr = readAll(made.folder + "/samples.exr");
        made.png = plimsoll::encodePaintedMapPng16({8, 8, std::vector<float>(64, 0.75f)});
        writeAll(made.folder + "/graph.json", kGraph);
        return made;
    }();
    return b;
}

std::string patched(const std::string& file, const std::uint8_t* data, std::size_t size) {
    if (size < 4) return file;
    const std::uint32_t raw =
        data[0] | (data[1] << 8) | (data[2] << 16) | (std::uint32_t(data[3]) << 24);
    std::string out = file;
    const std::size_t at = (raw & 0x7FFFFFFFu) % (file.size() + 1);
    if (raw & 0x80000000u) out.resize(at);
    for (std::size_t i = 4; i < size; ++i) {
        const std::size_t p = at + i - 4;
        if (p < out.size())
            out[p] = static_cast<char>(data[i]);
        else
            out += static_cast<char>(data[i]);
    }
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const Bundle& b = bundle();
    const int mode = data[0] % 3;
    ++data;
    --size;
    writeAll(b.folder + "/manifest.json",
             mode == 0 ? std::string(reinterpret_cast<const char*>(data), size) : kManifest);
    writeAll(b.folder + "/samples.exr", mode == 1 ? patched(b.exr, data, size) : b.exr);
    writeAll(b.folder + "/perm.png", mode == 2 ? patched(b.png, data, size) : b.png);
    std::string error;
    plimsoll_runtime::LoadOptions options;
    options.verifyChecksums = false;
    const auto loaded = plimsoll_runtime::loadBundle(b.folder, error, options);
    if (!loaded) {
        if (error.empty()) std::abort();
        return 0;
    }
    for (const plimsoll_runtime::Sample& s : loaded->samples()) {
        if (!std::isfinite(s.area) || !(s.area >= 0) || !std::isfinite(s.position.x)) std::abort();
    }
    return 0;
}
