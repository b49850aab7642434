// Loading a bundle folder (docs/bundle.md "Reading a bundle"): the same checks as the engine's
// verifyBundle, then the sample list, the water graph, its permeability and texel-to-node map.
#include "plimsoll_runtime/runtime.hpp"

#include "json.hpp"
#include "png.hpp"
#include "vec.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

namespace plimsoll_runtime {

namespace {

using json::Value;

bool readFile(const std::string& path, std::string& bytes, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = path + ": missing or cannot be opened";
        return false;
    }
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) {
        error = path + ": read error";
        return false;
    }
    return true;
}

/// Typed access to JSON members with errors naming the file and the member's path.
class Reader {
public:
    Reader(std::string file, std::string& error) : file_(std::move(file)), error_(error) {}

    bool fail(const std::string& path, const std::string& what) {
        error_ = file_ + ": " + path + ": " + what;
        return false;
    }
    const Value* member(const Value& object, const std::string& path, const std::string& key,
                        bool required = true) {
        const Value* v = object.find(key);
        if (!v && required) fail(path, "missing required member \"" + key + "\"");
        return v;
    }
    bool number(const Value& object, const std::string& path, const std::string& key,
                double& out, bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isNumber()) return fail(path + "." + key, std::string("expected a number, got ") + json::kindName(v->kind));
        out = v->number;
        return true;
    }
    bool integer(const Value& object, const std::string& path, const std::string& key,
                 long long& out, bool required = true) {
        double d = 0;
        if (!number(object, path, key, d, required)) return false;
        if (!object.find(key)) return true;
        if (d != std::floor(d) || std::abs(d) > 9.0e15) return fail(path + "." + key, "expected an integer");
        out = static_cast<long long>(d);
        return true;
    }
    bool string(const Value& object, const std::string& path, const std::string& key,
                std::string& out, bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isString()) return fail(path + "." + key, std::string("expected a string, got ") + json::kindName(v->kind));
        out = v->string;
        return true;
    }
    bool boolean(const Value& object, const std::string& path, const std::string& key, bool& out,
                 bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isBool()) return fail(path + "." + key, std::string("expected true or false, got ") + json::kindName(v->kind));
        out = v->boolean;
        return true;
    }
    bool vec3(const Value& object, const std::string& path, const std::string& key, Vec3& out,
              bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isArray() || v->array.size() != 3 || !v->array[0].isNumber() ||
            !v->array[1].isNumber() || !v->array[2].isNumber())
            return fail(path + "." + key, "expected an array of 3 numbers");
        out = {v->array[0].number, v->array[1].number, v->array[2].number};
        return true;
    }

private:
    std::string file_;
    std::string& error_;
};

bool readMass(Reader& r, const Value& v, const std::string& path, MassProperties& out) {
    if (!v.isObject()) return r.fail(path, "expected an object");
    if (!r.number(v, path, "mass", out.mass) || !r.number(v, path, "volume", out.volume) ||
        !r.vec3(v, path, "center_of_mass", out.centerOfMass))
        return false;
    const Value* inertia = r.member(v, path, "inertia");
    if (!inertia) return false;
    if (!inertia->isArray() || inertia->array.size() != 3)
        return r.fail(path + ".inertia", "expected a 3 x 3 array");
    for (int row = 0; row < 3; ++row) {
        const Value& line = inertia->array[row];
        if (!line.isArray() || line.array.size() != 3)
            return r.fail(path + ".inertia", "expected a 3 x 3 array");
        for (int col = 0; col < 3; ++col) {
            if (!line.array[col].isNumber()) return r.fail(path + ".inertia", "expected numbers");
            out.inertia[row][col] = line.array[col].number;
        }
    }
    if (!(out.mass > 0) || !std::isfinite(out.mass)) return r.fail(path + ".mass", "must be > 0");
    return true;
}

/// Reads float channels of an EXR file into one interleaved buffer.
bool readExrFloat(const std::string& path, const std::vector<std::string>& channels, int& width,
                  int& height, std::vector<float>& pixels, std::string& error) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        width = window.max.x - window.min.x + 1;
        height = window.max.y - window.min.y + 1;
        if (window.min.x != 0 || window.min.y != 0 || width <= 0 || height <= 0) {
            error = path + ": EXR data window does not start at (0, 0)";
            return false;
        }
        const std::size_t n = channels.size();
        pixels.assign(static_cast<std::size_t>(width) * height * n, 0.0f);
        Imf::FrameBuffer frame;
        for (std::size_t c = 0; c < n; ++c) {
            const Imf::Channel* channel = file.header().channels().findChannel(channels[c]);
            if (!channel) {
                error = path + ": EXR has no channel '" + channels[c] + "'";
                return false;
            }
            if (channel->type != Imf::FLOAT) {
                error = path + ": EXR channel '" + channels[c] + "' is not float32";
                return false;
            }
            frame.insert(channels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data() + c),
                                                 sizeof(float) * n, sizeof(float) * n * width));
        }
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return true;
    } catch (const std::exception& e) {
        error = path + ": cannot read EXR: " + e.what();
        return false;
    }
}

bool readExrUint(const std::string& path, const std::string& channelName, int& width, int& height,
                 std::vector<std::uint32_t>& pixels, std::string& error) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        width = window.max.x - window.min.x + 1;
        height = window.max.y - window.min.y + 1;
        if (window.min.x != 0 || window.min.y != 0 || width <= 0 || height <= 0) {
            error = path + ": EXR data window does not start at (0, 0)";
            return false;
        }
        const Imf::Channel* channel = file.header().channels().findChannel(channelName);
        if (!channel || channel->type != Imf::UINT) {
            error = path + ": EXR has no UINT channel '" + channelName + "'";
            return false;
        }
        pixels.assign(static_cast<std::size_t>(width) * height, 0u);
        Imf::FrameBuffer frame;
        frame.insert(channelName, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(pixels.data()),
                                             sizeof(std::uint32_t), sizeof(std::uint32_t) * width));
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return true;
    } catch (const std::exception& e) {
        error = path + ": cannot read EXR: " + e.what();
        return false;
    }
}

/// The engine's nearestNode (graph.h): distance to a box node's box, else to its centre; ties
/// to the nearer centre, then the lower index.
int nearestNode(const std::vector<GraphNode>& nodes, const Vec3& p) {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity(), bestCentre = best;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
        const GraphNode& n = nodes[j];
        double d;
        if (n.isBox()) {
            const Vec3 q = p - n.position;
            const Vec3 e{std::max(0.0, std::abs(q.x) - 0.5 * n.box.x),
                         std::max(0.0, std::abs(q.y) - 0.5 * n.box.y),
                         std::max(0.0, std::abs(q.z) - 0.5 * n.box.z)};
            d = norm(e);
        } else {
            d = norm(p - n.position);
        }
        const double centre = norm(n.position - p);
        if (d < best || (d == best && centre < bestCentre)) {
            best = d;
            bestCentre = centre;
            nearest = static_cast<int>(j);
        }
    }
    return nearest;
}

bool readGraph(const std::string& path, WaterGraph& graph, std::vector<GraphNode>& nodes,
               std::vector<GraphPipe>& pipes, std::string& error) {
    std::string text;
    if (!readFile(path, text, error)) return false;
    Value root;
    std::string parseError;
    if (!json::parse(text, root, parseError)) {
        error = path + ": malformed JSON: " + parseError;
        return false;
    }
    Reader r(path, error);
    if (!root.isObject()) return r.fail("$", "expected an object");
    long long version = 0;
    if (!r.integer(root, "$", "schema_version", version)) return false;
    if (version != 1)
        return r.fail("$.schema_version", "graph schema " + std::to_string(version) +
                                              " is not supported (this reader knows 1)");
    const Value* nodeList = r.member(root, "$", "nodes");
    const Value* pipeList = r.member(root, "$", "pipes");
    if (!nodeList || !pipeList) return false;
    if (!nodeList->isArray() || nodeList->array.empty()) return r.fail("$.nodes", "expected a non-empty array");
    if (!pipeList->isArray()) return r.fail("$.pipes", "expected an array");
    for (std::size_t i = 0; i < nodeList->array.size(); ++i) {
        const Value& v = nodeList->array[i];
        const std::string at = "$.nodes[" + std::to_string(i) + "]";
        if (!v.isObject()) return r.fail(at, "expected an object");
        GraphNode n;
        if (!r.string(v, at, "id", n.id) || !r.string(v, at, "name", n.name, false) ||
            !r.vec3(v, at, "position", n.position) || !r.number(v, at, "capacity", n.capacity) ||
            !r.number(v, at, "water", n.water, false) || !r.boolean(v, at, "sealed", n.sealed, false) ||
            !r.vec3(v, at, "box", n.box, false))
            return false;
        if (n.id.empty()) return r.fail(at + ".id", "must not be empty");
        for (const GraphNode& other : nodes) {
            if (other.id == n.id) return r.fail(at + ".id", "\"" + n.id + "\" is used twice");
        }
        if (!(n.capacity > 0) || !std::isfinite(n.capacity)) return r.fail(at + ".capacity", "must be > 0");
        if (!(n.water >= 0) || n.water > n.capacity) return r.fail(at + ".water", "must be in 0..capacity");
        if (!finite(n.position)) return r.fail(at + ".position", "must be finite");
        const bool zeroBox = n.box.x == 0 && n.box.y == 0 && n.box.z == 0;
        if (!zeroBox && !(n.isBox() && finite(n.box))) return r.fail(at + ".box", "edges must all be > 0");
        nodes.push_back(std::move(n));
    }
    for (std::size_t i = 0; i < pipeList->array.size(); ++i) {
        const Value& v = pipeList->array[i];
        const std::string at = "$.pipes[" + std::to_string(i) + "]";
        if (!v.isObject()) return r.fail(at, "expected an object");
        GraphPipe p;
        if (!r.string(v, at, "a", p.a) || !r.string(v, at, "b", p.b) ||
            !r.number(v, at, "radius", p.radius, false) || !r.number(v, at, "length", p.length, false) ||
            !r.boolean(v, at, "open", p.open, false))
            return false;
        for (std::size_t j = 0; j < nodes.size(); ++j) {
            if (nodes[j].id == p.a && p.nodeA < 0) p.nodeA = static_cast<int>(j);
            if (nodes[j].id == p.b && p.nodeB < 0) p.nodeB = static_cast<int>(j);
        }
        if (p.nodeA < 0 || p.nodeB < 0)
            return r.fail(at, "no node \"" + (p.nodeA < 0 ? p.a : p.b) + "\"");
        if (p.nodeA == p.nodeB) return r.fail(at, "joins a node to itself");
        if (!(p.radius > 0) || !std::isfinite(p.radius) || !(p.length >= 0) || !std::isfinite(p.length))
            return r.fail(at, "radius must be > 0 and length >= 0");
        if (!(p.length > 0) && !(norm(nodes[p.nodeA].position - nodes[p.nodeB].position) > 0))
            return r.fail(at, "its nodes coincide, so it needs a length > 0");
        pipes.push_back(std::move(p));
    }
    (void)graph;
    return true;
}

}  // namespace

bool loadBundleImpl(const std::string& folderIn, Bundle& b, std::string& error, bool verify) {
    std::string folder = folderIn;
    while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
    b.folder_ = folder;
    const std::string manifestPath = folder + "/manifest.json";
    std::string text;
    if (!readFile(manifestPath, text, error)) return false;
    Value m;
    std::string parseError;
    if (!json::parse(text, m, parseError)) {
        error = manifestPath + ": malformed manifest: " + parseError;
        return false;
    }
    Reader r(manifestPath, error);
    if (!m.isObject()) return r.fail("$", "malformed manifest: expected an object");
    const Value* format = m.find("format");
    if (!format || !format->isString() || format->string != "plimsoll-runtime-bundle") {
        error = manifestPath + ": not a Plimsoll runtime bundle (\"format\" is not "
                               "\"plimsoll-runtime-bundle\")";
        return false;
    }
    long long major = 0, minor = 0;
    if (!r.integer(m, "$", "schema_version", major) || !r.integer(m, "$", "schema_minor", minor))
        return false;
    b.schemaMajor_ = static_cast<int>(major);
    b.schemaMinor_ = static_cast<int>(minor);
    if (major != kSchemaMajor) {
        const std::string version = std::to_string(major) + "." + std::to_string(minor);
        error = manifestPath + ": bundle schema " + version +
                (major > kSchemaMajor ? " is newer than" : " is older than") + " this reader's " +
                std::to_string(kSchemaMajor) + ".x: export the bundle again with this version of plimsoll" +
                (major > kSchemaMajor ? " or update the runtime" : "");
        return false;
    }

    // Files: every one inside the folder, with its size and checksum.
    const Value* files = r.member(m, "$", "files");
    if (!files) return false;
    if (!files->isArray()) return r.fail("$.files", "expected an array");
    bool hasTexelNodes = false;
    std::vector<std::string> listed;
    for (std::size_t i = 0; i < files->array.size(); ++i) {
        const Value& f = files->array[i];
        const std::string at = "$.files[" + std::to_string(i) + "]";
        if (!f.isObject()) return r.fail(at, "expected an object");
        std::string path, sha;
        long long bytes = 0;
        if (!r.string(f, at, "path", path) || !r.string(f, at, "sha256", sha) ||
            !r.integer(f, at, "bytes", bytes))
            return false;
        bool escapes = path.empty() || path.front() == '/' || path.find('\\') != std::string::npos;
        for (std::size_t start = 0; !escapes && start <= path.size();) {
            const std::size_t end = std::min(path.find('/', start), path.size());
            if (path.compare(start, end - start, "..") == 0 && end - start == 2) escapes = true;
            start = end + 1;
        }
        if (escapes) return r.fail(at + ".path", "file path \"" + path + "\" leaves the bundle");
        if (path == "texel_nodes.exr") hasTexelNodes = true;
        listed.push_back(path);
        if (!verify) continue;
        const std::string full = folder + "/" + path;
        std::string content;
        if (!readFile(full, content, error)) return false;
        if (static_cast<long long>(content.size()) != bytes) {
            error = full + ": " + std::to_string(content.size()) + " bytes, the manifest says " +
                    std::to_string(bytes) + " (truncated or replaced)";
            return false;
        }
        const std::string actual = sha256Hex(content.data(), content.size());
        if (actual != sha) {
            error = full + ": SHA-256 " + actual + " does not match the manifest's " + sha;
            return false;
        }
    }

    r.string(m, "$", "body", b.body_, false);
    long long size = 0, count = 0;
    if (!r.integer(m, "$", "texture_size", size) || !r.integer(m, "$", "texel_samples", count))
        return false;
    if (size < 1 || size > 65536) return r.fail("$.texture_size", "out of range");
    if (count < 0) return r.fail("$.texel_samples", "must be >= 0");
    b.textureSize_ = static_cast<int>(size);
    const Value* placement = r.member(m, "$", "uv_placement");
    if (!placement) return false;
    double uvScale = 1;
    Vec3 uvOffset;
    {
        if (!r.number(*placement, "$.uv_placement", "scale", uvScale)) return false;
        const Value* offset = r.member(*placement, "$.uv_placement", "offset");
        if (!offset) return false;
        if (!offset->isArray() || offset->array.size() != 2 || !offset->array[0].isNumber() ||
            !offset->array[1].isNumber())
            return r.fail("$.uv_placement.offset", "expected an array of 2 numbers");
        uvOffset = {offset->array[0].number, offset->array[1].number, 0};
        if (!(uvScale > 0)) return r.fail("$.uv_placement.scale", "must be > 0");
    }
    const Value* massProps = r.member(m, "$", "mass_properties");
    if (!massProps) return false;
    const Value* texture = r.member(*massProps, "$.mass_properties", "texture");
    if (!texture || !readMass(r, *texture, "$.mass_properties.texture", b.mass_)) return false;
    if (const Value* hydro = m.find("hydrodynamics")) {
        if (!r.number(*hydro, "$.hydrodynamics", "drag_coefficient", b.fluid_.dragCoefficient, false) ||
            !r.number(*hydro, "$.hydrodynamics", "friction_coefficient", b.fluid_.frictionCoefficient, false) ||
            !r.number(*hydro, "$.hydrodynamics", "linear_damping", b.linearDamping_, false) ||
            !r.number(*hydro, "$.hydrodynamics", "angular_damping", b.angularDamping_, false))
            return false;
    }

    // The sample list (bake_io.cpp's layout: channels x y px py pz ax ay az area coverage).
    const std::string samplesPath = folder + "/samples.exr";
    static const std::vector<std::string> kChannels = {"x",  "y",  "px",   "py",      "pz",
                                                      "ax", "ay", "az", "area", "coverage"};
    int width = 0, height = 0;
    std::vector<float> px;
    if (!readExrFloat(samplesPath, kChannels, width, height, px, error)) return false;
    if (static_cast<std::size_t>(count) > static_cast<std::size_t>(width) * height) {
        error = samplesPath + ": holds fewer samples than the manifest's texel_samples (" +
                std::to_string(count) + ")";
        return false;
    }
    b.samples_.resize(static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < b.samples_.size(); ++i) {
        const float* in = &px[i * kChannels.size()];
        const int x = static_cast<int>(in[0]), y = static_cast<int>(in[1]);
        if (x < 0 || y < 0 || x >= size || y >= size || !(in[9] > 0.0f)) {
            error = samplesPath + ": sample " + std::to_string(i) + " is not a covered texel of the texture";
            return false;
        }
        Sample& s = b.samples_[i];
        s.texel = static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(size) + static_cast<std::uint32_t>(x);
        s.position = {in[2], in[3], in[4]};
        s.areaVector = {in[5], in[6], in[7]};
        s.area = in[8];
        s.coverage = in[9];
    }

    // The water graph.
    const Value* graphInfo = m.find("water_graph");
    if (graphInfo && !graphInfo->isNull()) {
        const std::string at = "$.water_graph";
        if (!graphInfo->isObject()) return r.fail(at, "expected an object or null");
        auto graph = std::make_unique<WaterGraph>();
        GraphSettings& gs = graph->settings_;
        std::string graphFile, inflow = "linear", flow = "poiseuille";
        double seed = 1;
        if (!r.string(*graphInfo, at, "path", graphFile) ||
            !r.number(*graphInfo, at, "permeability", gs.permeability, false) ||
            !r.string(*graphInfo, at, "inflow", inflow, false) ||
            !r.number(*graphInfo, at, "inflow_rate", gs.inflowRate, false) ||
            !r.number(*graphInfo, at, "discharge_coefficient", gs.dischargeCoefficient, false) ||
            !r.string(*graphInfo, at, "flow", flow, false) ||
            !r.number(*graphInfo, at, "diffusion_pressure", gs.diffusionPressure, false) ||
            !r.boolean(*graphInfo, at, "free_surface", gs.freeSurface, false) ||
            !r.number(*graphInfo, at, "seed", seed, false))
            return false;
        if (inflow != "linear" && inflow != "torricelli")
            return r.fail(at + ".inflow", "unknown inflow model \"" + inflow + "\"");
        if (flow != "poiseuille" && flow != "diffusion")
            return r.fail(at + ".flow", "unknown flow model \"" + flow + "\"");
        if (!(seed >= 0)) return r.fail(at + ".seed", "must be >= 0");
        gs.torricelli = inflow == "torricelli";
        gs.diffusion = flow == "diffusion";
        gs.seed = static_cast<std::uint64_t>(seed);
        if (!readGraph(folder + "/" + graphFile, *graph, graph->nodes_, graph->pipes_, error))
            return false;

        // The node each sample feeds: texel_nodes.exr where the bundle has it, for texels with
        // one entry (the map has one value per texel); the engine's rule for the rest.
        const std::size_t nodeCount = graph->nodes_.size();
        // 1.1 names the file in water_graph.texel_nodes; it is also listed in `files`.
        std::string texelNodesFile = hasTexelNodes ? "texel_nodes.exr" : "";
        if (!r.string(*graphInfo, at, "texel_nodes", texelNodesFile, false)) return false;
        std::vector<std::uint32_t> texelNodes;
        if (!texelNodesFile.empty() &&
            std::find(listed.begin(), listed.end(), texelNodesFile) == listed.end())
            return r.fail(at + ".texel_nodes", "\"" + texelNodesFile + "\" is not in the manifest's files");
        if (!texelNodesFile.empty()) {
            const std::string path = folder + "/" + texelNodesFile;
            int w = 0, h = 0;
            if (!readExrUint(path, "node", w, h, texelNodes, error)) return false;
            if (w != size || h != size) {
                error = path + ": " + std::to_string(w) + " x " + std::to_string(h) +
                        ", the texture is " + std::to_string(size) + " x " + std::to_string(size);
                return false;
            }
            b.texelNodesFromFile_ = true;
        }
        graph->sampleNodes_.resize(b.samples_.size());
        for (std::size_t i = 0; i < b.samples_.size(); ++i) {
            const Sample& s = b.samples_[i];
            const bool shared = (i > 0 && b.samples_[i - 1].texel == s.texel) ||
                                (i + 1 < b.samples_.size() && b.samples_[i + 1].texel == s.texel);
            int node = -1;
            if (!texelNodes.empty() && !shared) {
                const std::uint32_t x = s.texel % size, y = s.texel / size;
                const std::uint32_t v = texelNodes[(static_cast<std::size_t>(size) - 1 - y) * size + x];
                if (v == 0 || v > nodeCount) {
                    error = folder + "/" + texelNodesFile + ": texel (" + std::to_string(x) + ", " +
                            std::to_string(y) + ") is covered but maps to " + std::to_string(v) +
                            " (expected 1.." + std::to_string(nodeCount) + ")";
                    return false;
                }
                node = static_cast<int>(v) - 1;
            } else {
                node = nearestNode(graph->nodes_, s.position);
            }
            graph->sampleNodes_[i] = node;
        }

        // Permeability per sample: the painted map at the texel centre, as the engine's
        // sampleAtTexels (bilinear, clamped), times the project's scale.
        const Value* maps = m.find("painted_maps");
        const Value* perm = maps ? maps->find("permeability") : nullptr;
        if (perm && !perm->isNull()) {
            std::string mapFile;
            if (!r.string(*perm, "$.painted_maps.permeability", "path", mapFile)) return false;
            const std::string path = folder + "/" + mapFile;
            std::string bytes, pngError;
            if (!readFile(path, bytes, error)) return false;
            GreyImage map;
            if (!decodePng(bytes, map, pngError)) {
                error = path + ": cannot read painted map: " + pngError;
                return false;
            }
            const double n = size;
            for (std::size_t i = 0; i < b.samples_.size(); ++i) {
                const std::uint32_t texel = b.samples_[i].texel;
                const double tu = (texel % size + 0.5) / n, tv = (texel / size + 0.5) / n;
                const double u = (tu - uvOffset.x) / uvScale, v = (tv - uvOffset.y) / uvScale;
                const double fx = std::clamp(u * map.width - 0.5, 0.0, map.width - 1.0);
                const double fy = std::clamp((1.0 - v) * map.height - 0.5, 0.0, map.height - 1.0);
                const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
                const int x1 = std::min(x0 + 1, map.width - 1), y1 = std::min(y0 + 1, map.height - 1);
                const double ax = fx - x0, ay = fy - y0;
                auto at = [&](int px, int py) {
                    return static_cast<double>(map.values[static_cast<std::size_t>(py) * map.width + px]);
                };
                const double value = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) +
                                     ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
                const double k = std::clamp(gs.permeability * value, 0.0, 1.0);
                if (!(k > 0)) continue;
                const int node = graph->sampleNodes_[i];
                if (node < 0 || graph->nodes_[node].sealed) continue;
                graph->exchange_.push_back({b.samples_[i].position, k * b.samples_[i].area,
                                            static_cast<std::uint32_t>(node)});
            }
        }
        graph->prepare();
        b.graph_ = std::move(graph);
    }
    return true;
}

std::unique_ptr<Bundle> loadBundle(const std::string& folder, std::string& error,
                                   const LoadOptions& options) {
    auto bundle = std::make_unique<Bundle>();
    error.clear();
    try {
        if (!loadBundleImpl(folder, *bundle, error, options.verifyChecksums)) return nullptr;
    } catch (const std::exception& e) {
        error = folder + ": " + e.what();
        return nullptr;
    }
    return bundle;
}

}  // namespace plimsoll_runtime
