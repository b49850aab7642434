// Loading a bundle folder (docs/bundle.md "Reading a bundle"): the same checks as the engine's
// verifyBundle, then the sample list, the water graph, its permeability and texel-to-node map.
#include "plimsoll_runtime/runtime.hpp"
#include "plimsoll_runtime.h"

#include "plimsoll_eval/cummins.hpp"
#include "plimsoll_eval/format.hpp"

#include "exr.hpp"
#include "json.hpp"
#include "png.hpp"
#include "vec.hpp"
#include "world.hpp"

#include "plimsoll_eval/nearest_node.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>
#include <string_view>
#include <unordered_map>

namespace plimsoll_runtime {

/// Where the loader gets a bundle's files: a folder, memory or the caller's callbacks. `read`
/// is given a path already checked to stay inside the bundle; it fills `bytes` with the whole
/// file when it is at most `maxBytes`, else sets `error` to "name/path: the problem".
struct BundleSource {
    std::string name;
    std::function<bool(const std::string& relative, std::uint64_t maxBytes, std::string& bytes,
                       std::string& error)>
        read;
};

namespace {

using json::Value;
namespace format = plimsoll_eval;

// What the loader reads, at most (the engine's limits.h, restated: the runtime builds alone).
constexpr std::uint64_t kMaxJsonBytes = 256ull << 20;  ///< kMaxJsonFileBytes
constexpr std::uint64_t kMaxFileBytes = 1ull << 30;    ///< kMaxDataFileBytes
constexpr long long kMaxTextureSide = 8192;            ///< kMaxTextureSize
constexpr std::size_t kMaxLevels = 16;                 ///< a ladder of 16 .. 8192 has 10
constexpr std::uint64_t kMaxGraphNodes = 100000;       ///< kMaxGraphNodes
constexpr std::uint64_t kMaxGraphPipes = 16 * kMaxGraphNodes;

/// A path a manifest names, inside the bundle: not empty, not absolute, no "..", no backslash,
/// no NUL byte (which would cut the path short and open another file).
bool staysInside(const std::string& path) {
    if (path.empty() || path.front() == '/' || path.find('\\') != std::string::npos ||
        path.find('\0') != std::string::npos)
        return false;
    for (std::size_t start = 0; start <= path.size();) {
        const std::size_t end = std::min(path.find('/', start), path.size());
        if (end - start == 2 && path.compare(start, 2, "..") == 0) return false;
        start = end + 1;
    }
    return true;
}

/// `path` (one that staysInside) without empty and "." components: "./a//b" is "a/b".
std::string normalPath(const std::string& path) {
    std::string out;
    for (std::size_t start = 0; start <= path.size();) {
        const std::size_t end = std::min(path.find('/', start), path.size());
        const std::string_view part(path.data() + start, end - start);
        if (!part.empty() && part != ".") out.append(out.empty() ? "" : "/").append(part);
        start = end + 1;
    }
    return out;
}

std::string tooLarge(const std::string& full, std::uint64_t bytes, std::uint64_t maxBytes) {
    return full + ": " + std::to_string(bytes) + " bytes, more than the " +
           std::to_string(maxBytes) + " allowed";
}
const char* const kShrank = ": read error (the file shrank while read?)";

}  // namespace

bool readFileInside(const std::string& folder, const std::string& relative, std::uint64_t maxBytes,
                    std::string& bytes, std::string& error, FileReadProblem* problem) {
    FileReadProblem ignored = FileReadProblem::None;
    FileReadProblem& why = problem ? *problem : ignored;
    const std::string full = folder + "/" + relative;
    if (!staysInside(relative)) {
        why = FileReadProblem::Outside;
        error = full + ": the path leaves its folder";
        return false;
    }
    int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir < 0) {
        why = errno == ENOENT ? FileReadProblem::Missing : FileReadProblem::Unreadable;
        error = errno == ENOENT ? full + ": missing (there is no folder " + folder + ")"
                                : folder + ": cannot open the folder: " + std::strerror(errno);
        return false;
    }
    int fd = -1;
    for (std::size_t start = 0;;) {
        const std::size_t slash = relative.find('/', start);
        const std::string part =
            relative.substr(start, slash == std::string::npos ? slash : slash - start);
        const bool last = slash == std::string::npos;
        const int next = ::openat(dir, part.c_str(),
                                  last ? O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY
                                       : O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        const int openError = errno;
        ::close(dir);
        if (next < 0) {
            const bool link = openError == ELOOP || openError == ENOTDIR;
            why = openError == ENOENT ? FileReadProblem::Missing
                  : link              ? FileReadProblem::Link
                                      : FileReadProblem::Unreadable;
            error =
                full + (openError == ENOENT ? ": missing"
                        : link ? ": is (or passes through) a symbolic link, which is not followed"
                               : std::string(": cannot be opened: ") + std::strerror(openError));
            return false;
        }
        if (last) {
            fd = next;
            break;
        }
        dir = next;
        start = slash + 1;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        why = FileReadProblem::NotRegular;
        error = full + ": not a regular file (a FIFO, a device or a folder)";
        return false;
    }
    if (static_cast<std::uint64_t>(st.st_size) > maxBytes) {
        ::close(fd);
        why = FileReadProblem::TooLarge;
        error = tooLarge(full, static_cast<std::uint64_t>(st.st_size), maxBytes);
        return false;
    }
    bytes.assign(static_cast<std::size_t>(st.st_size), '\0');
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::read(fd, &bytes[done], bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
    }
    ::close(fd);
    if (done != bytes.size()) {
        why = FileReadProblem::Unreadable;
        error = full + kShrank;
        return false;
    }
    why = FileReadProblem::None;
    return true;
}

namespace {

BundleSource folderSource(std::string folder) {
    while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
    BundleSource source;
    source.name = folder;
    source.read = [folder](const std::string& relative, std::uint64_t maxBytes, std::string& bytes,
                           std::string& error) {
        return readFileInside(folder, relative, maxBytes, bytes, error);
    };
    return source;
}

/// The caller's files: sizes checked before anything is allocated, exactly `size` bytes read.
BundleSource callbackSource(const FileCallbacks& callbacks, const std::string& name) {
    BundleSource source;
    source.name = name;
    source.read = [&callbacks, name](const std::string& relative, std::uint64_t maxBytes,
                                     std::string& bytes, std::string& error) {
        const std::string full = name + "/" + relative;
        void* file = callbacks.open(relative);
        if (!file) {
            error = full + ": missing";
            return false;
        }
        struct Closer {
            const FileCallbacks& callbacks;
            void* file;
            ~Closer() { callbacks.close(file); }
        } closer{callbacks, file};
        const long long size = callbacks.size(file);
        if (size < 0) {
            error = full + ": the file callbacks cannot give its size";
            return false;
        }
        if (static_cast<std::uint64_t>(size) > maxBytes) {
            error = tooLarge(full, static_cast<std::uint64_t>(size), maxBytes);
            return false;
        }
        bytes.assign(static_cast<std::size_t>(size), '\0');
        std::size_t done = 0;
        while (done < bytes.size()) {
            const long long n = callbacks.read(file, done, &bytes[done], bytes.size() - done);
            if (n < 0) {
                error = full + ": the file callbacks report a read error";
                return false;
            }
            if (n == 0) break;
            if (static_cast<std::uint64_t>(n) > bytes.size() - done) {
                error = full + ": the read callback returned more bytes than asked for";
                return false;
            }
            done += static_cast<std::size_t>(n);
        }
        if (done != bytes.size()) {
            error = full + kShrank;
            return false;
        }
        return true;
    };
    return source;
}

/// Typed access to JSON members with errors naming the file and the member's path.
class Reader {
public:
    /// `every`: each fail adds a line to `error` (a reader that reports every problem);
    /// otherwise the last fail is the message.
    Reader(std::string file, std::string& error, bool every = false)
        : file_(std::move(file)), error_(error), every_(every) {}

    bool fail(const std::string& path, const std::string& what) {
        std::string line = file_ + ": " + path + ": " + what;
        if (every_ && !error_.empty()) {
            error_ += "\n" + line;
        } else {
            error_ = std::move(line);
        }
        return false;
    }
    /// Fails once for each member of `object` that is not one of `known`.
    bool knownMembers(const Value& object, const std::string& path,
                      std::initializer_list<std::string_view> known) {
        bool ok = true;
        for (const auto& [key, value] : object.object) {
            (void)value;
            if (std::find(known.begin(), known.end(), key) == known.end())
                ok = fail(path + "." + key, "unknown member");
        }
        return ok;
    }
    const Value* member(const Value& object, const std::string& path, const std::string& key,
                        bool required = true) {
        const Value* v = object.find(key);
        if (!v && required) fail(path, "missing required member \"" + key + "\"");
        return v;
    }
    bool number(const Value& object, const std::string& path, const std::string& key, double& out,
                bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isNumber())
            return fail(path + "." + key,
                        std::string("expected a number, got ") + json::kindName(v->kind));
        out = v->number;
        return true;
    }
    bool integer(const Value& object, const std::string& path, const std::string& key,
                 long long& out, bool required = true) {
        double d = 0;
        if (!number(object, path, key, d, required)) return false;
        if (!object.find(key)) return true;
        if (d != std::floor(d) || std::abs(d) > 9.0e15)
            return fail(path + "." + key, "expected an integer");
        out = static_cast<long long>(d);
        return true;
    }
    bool string(const Value& object, const std::string& path, const std::string& key,
                std::string& out, bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isString())
            return fail(path + "." + key,
                        std::string("expected a string, got ") + json::kindName(v->kind));
        out = v->string;
        return true;
    }
    bool boolean(const Value& object, const std::string& path, const std::string& key, bool& out,
                 bool required = true) {
        const Value* v = member(object, path, key, required);
        if (!v) return !required;
        if (!v->isBool())
            return fail(path + "." + key,
                        std::string("expected true or false, got ") + json::kindName(v->kind));
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
    bool every_ = false;
};

/// The manifest's "radiation" (schema 1.3): every number finite, the rest volume > 0, A_inf
/// symmetric with a diagonal >= 0, at most format::kMaxMemoryTerms filters per mode, each with a
/// gain >= 0 and a frequency and damping ratio > 0 (what keeps the memory passive and stable).
bool readRadiation(Reader& r, const Value& v, const std::string& path, Radiation& out) {
    if (!v.isObject()) return r.fail(path, "expected an object or null");
    if (!r.number(v, path, "rest_volume", out.restVolume)) return false;
    if (!(out.restVolume > 0) || !std::isfinite(out.restVolume))
        return r.fail(path + ".rest_volume", "must be finite and > 0");
    const Value* added = r.member(v, path, "added_mass_infinity");
    if (!added) return false;
    const std::string addedPath = path + ".added_mass_infinity";
    if (!added->isArray() || added->array.size() != 6)
        return r.fail(addedPath, "expected 6 rows of 6 numbers");
    for (int i = 0; i < 6; ++i) {
        const Value& row = added->array[i];
        if (!row.isArray() || row.array.size() != 6)
            return r.fail(addedPath, "expected 6 rows of 6 numbers");
        for (int j = 0; j < 6; ++j) {
            if (!row.array[j].isNumber() || !std::isfinite(row.array[j].number))
                return r.fail(addedPath + "[" + std::to_string(i) + "][" + std::to_string(j) + "]",
                              "expected a finite number");
            out.addedMassInfinity[i][j] = row.array[j].number;
        }
    }
    // A mode with no added mass (a sphere's yaw) comes out of the panel method as a tiny
    // number of either sign: only a diagonal clearly below zero is wrong.
    double largest = 0;
    for (int i = 0; i < 6; ++i) largest = std::max(largest, std::abs(out.addedMassInfinity[i][i]));
    for (int i = 0; i < 6; ++i) {
        if (out.addedMassInfinity[i][i] < -1e-6 * largest)
            return r.fail(addedPath + "[" + std::to_string(i) + "][" + std::to_string(i) + "]",
                          "must be >= 0");
        for (int j = 0; j < i; ++j) {
            const double a = out.addedMassInfinity[i][j], b = out.addedMassInfinity[j][i];
            if (std::abs(a - b) > 1e-9 * (std::abs(a) + std::abs(b)) + 1e-300)
                return r.fail(addedPath, "is not symmetric");
        }
    }
    const Value* memory = r.member(v, path, "memory");
    if (!memory) return false;
    if (!memory->isArray() || memory->array.size() != 6)
        return r.fail(path + ".memory", "expected 6 lists of filters (one per mode)");
    for (int mode = 0; mode < 6; ++mode) {
        const std::string modePath = path + ".memory[" + std::to_string(mode) + "]";
        const Value& terms = memory->array[mode];
        if (!terms.isArray()) return r.fail(modePath, "expected a list of filters");
        if (terms.array.size() > format::kMaxMemoryTerms)
            return r.fail(modePath, std::to_string(terms.array.size()) +
                                        " filters, more than the limit " +
                                        std::to_string(format::kMaxMemoryTerms));
        for (std::size_t k = 0; k < terms.array.size(); ++k) {
            const std::string termPath = modePath + "[" + std::to_string(k) + "]";
            const Value& term = terms.array[k];
            if (!term.isObject()) return r.fail(termPath, "expected an object");
            RadiationTerm t;
            if (!r.number(term, termPath, "gain", t.gain) ||
                !r.number(term, termPath, "frequency", t.frequency) ||
                !r.number(term, termPath, "damping_ratio", t.dampingRatio))
                return false;
            if (!(t.gain >= 0) || !std::isfinite(t.gain))
                return r.fail(termPath + ".gain", "must be finite and >= 0");
            if (!(t.frequency > 0) || !std::isfinite(t.frequency))
                return r.fail(termPath + ".frequency", "must be finite and > 0");
            if (!(t.dampingRatio > 0) || !std::isfinite(t.dampingRatio))
                return r.fail(termPath + ".damping_ratio", "must be finite and > 0");
            out.memory[mode].push_back(t);
        }
    }
    return true;
}

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
    bool finiteInertia = std::isfinite(out.volume) && finite(out.centerOfMass);
    for (const auto& row : out.inertia)
        for (const double v : row) finiteInertia = finiteInertia && std::isfinite(v);
    if (!finiteInertia) return r.fail(path, "volume, center_of_mass and inertia must be finite");
    return true;
}

/// Runs `checks` in order: every one where every problem is wanted, up to the first that
/// fails otherwise. True when all passed.
template <class... Checks>
bool checkEach(bool every, Checks&&... checks) {
    bool ok = true;
    ((ok = (ok || every) ? checks() && ok : false), ...);
    return ok;
}

/// A node's or pipe's id: a string, or in authoring an integer too (kept as its decimal text).
bool readId(Reader& r, const Value& v, const std::string& at, const char* key, bool integers,
            std::string& out) {
    const Value* id = v.find(key);
    if (integers && id && id->isNumber() && id->number == std::floor(id->number) &&
        std::abs(id->number) < 9.0e15) {
        out = std::to_string(static_cast<long long>(id->number));
        return true;
    }
    return r.string(v, at, key, out);
}

bool readGraphNode(Reader& r, const Value& v, const std::string& at, bool authoring, GraphNode& n) {
    if (!v.isObject()) return r.fail(at, "expected an object");
    return checkEach(
        authoring,
        [&] {
            return !authoring ||
                   r.knownMembers(v, at,
                                  {"id", "name", "position", "capacity", "water", "sealed", "box"});
        },
        [&] { return readId(r, v, at, "id", authoring, n.id); },
        [&] { return r.string(v, at, "name", n.name, false); },
        [&] { return r.vec3(v, at, "position", n.position); },
        [&] { return r.number(v, at, "capacity", n.capacity); },
        [&] { return r.number(v, at, "water", n.water, false); },
        [&] { return r.boolean(v, at, "sealed", n.sealed, false); },
        [&] { return r.vec3(v, at, "box", n.box, false); });
}

bool readGraphPipe(Reader& r, const Value& v, const std::string& at, bool authoring, GraphPipe& p) {
    if (!v.isObject()) return r.fail(at, "expected an object");
    return checkEach(
        authoring,
        [&] {
            return !authoring || r.knownMembers(v, at, {"a", "b", "radius", "length", "open"});
        },
        [&] { return readId(r, v, at, "a", authoring, p.a); },
        [&] { return readId(r, v, at, "b", authoring, p.b); },
        [&] { return r.number(v, at, "radius", p.radius, authoring); },
        [&] { return r.number(v, at, "length", p.length, false); },
        [&] { return r.boolean(v, at, "open", p.open, false); });
}

/// The graph's own rules for one node (a bundle's graph; authoring leaves them to the engine).
bool checkGraphNode(Reader& r, const std::string& at, const GraphNode& n) {
    if (n.id.empty()) return r.fail(at + ".id", "must not be empty");
    if (!(n.capacity > 0) || !std::isfinite(n.capacity))
        return r.fail(at + ".capacity", "must be > 0");
    if (!(n.water >= 0) || !(n.water <= n.capacity))
        return r.fail(at + ".water", "must be in 0..capacity");
    if (!finite(n.position)) return r.fail(at + ".position", "must be finite");
    const bool zeroBox = n.box.x == 0 && n.box.y == 0 && n.box.z == 0;
    if (!zeroBox && !(n.isBox() && finite(n.box)))
        return r.fail(at + ".box", "edges must all be > 0");
    return true;
}

/// The graph's own rules for one pipe whose node indices are set (a bundle's graph).
bool checkGraphPipe(Reader& r, const std::string& at, const GraphPipe& p,
                    const std::vector<GraphNode>& nodes) {
    if (p.nodeA < 0 || p.nodeB < 0)
        return r.fail(at, "no node \"" + (p.nodeA < 0 ? p.a : p.b) + "\"");
    if (p.nodeA == p.nodeB) return r.fail(at, "joins a node to itself");
    if (!(p.radius > 0) || !std::isfinite(p.radius) || !(p.length >= 0) || !std::isfinite(p.length))
        return r.fail(at, "radius must be > 0 and length >= 0");
    if (!(p.length > 0) && !(norm(nodes[p.nodeA].position - nodes[p.nodeB].position) > 0))
        return r.fail(at, "its nodes coincide, so it needs a length > 0");
    return true;
}

/// graph.json's root: its schema version, and its node and pipe lists within the limits.
bool readGraphRoot(Reader& r, const Value& root, bool authoring, const Value*& nodeList,
                   const Value*& pipeList, GraphJsonProblem& problem) {
    problem = GraphJsonProblem::Content;
    if (!root.isObject()) return r.fail("$", "expected an object");
    long long version = 0;
    const bool knownOk =
        !authoring || r.knownMembers(root, "$", {"schema_version", "name", "nodes", "pipes"});
    if (!r.integer(root, "$", "schema_version", version)) return false;
    if (version > format::kGraphSchemaVersion) {
        problem = GraphJsonProblem::NewerSchema;
        return r.fail("$.schema_version", std::to_string(version) +
                                              " is newer than this reader knows (" +
                                              std::to_string(format::kGraphSchemaVersion) + ")");
    }
    if (version < 1) return r.fail("$.schema_version", "must be 1 or more");
    nodeList = r.member(root, "$", "nodes");
    pipeList = r.member(root, "$", "pipes", !authoring);
    if (!nodeList || (!pipeList && !authoring)) return false;
    if (!nodeList->isArray() || (nodeList->array.empty() && !authoring))
        return r.fail("$.nodes", authoring ? "expected an array" : "expected a non-empty array");
    if (pipeList && !pipeList->isArray()) return r.fail("$.pipes", "expected an array");
    const std::size_t pipeCount = pipeList ? pipeList->array.size() : 0;
    if (nodeList->array.size() > kMaxGraphNodes || pipeCount > kMaxGraphPipes) {
        problem = GraphJsonProblem::Limit;
        return r.fail("$", std::to_string(nodeList->array.size()) + " nodes and " +
                               std::to_string(pipeCount) + " pipes, more than the limits " +
                               "kMaxGraphNodes = " + std::to_string(kMaxGraphNodes) +
                               " and kMaxGraphPipes = " + std::to_string(kMaxGraphPipes));
    }
    return knownOk;
}

}  // namespace

bool readGraphJson(const std::string& source, const std::string& text, GraphJsonMode mode,
                   std::vector<GraphNode>& nodes, std::vector<GraphPipe>& pipes,
                   GraphJsonProblem& problem, std::string& error) {
    const bool authoring = mode == GraphJsonMode::Authoring;
    nodes.clear();
    pipes.clear();
    error.clear();
    Value root;
    std::string parseError;
    if (!json::parse(text, root, parseError)) {
        // The parser's one refusal of a size: nesting past kMaxJsonDepth, which it names.
        problem = parseError.find("kMaxJsonDepth") != std::string::npos ? GraphJsonProblem::Limit
                                                                        : GraphJsonProblem::Syntax;
        error = source + ": malformed JSON: " + parseError;
        return false;
    }
    Reader r(source, error, authoring);
    const Value* nodeList = nullptr;
    const Value* pipeList = nullptr;
    bool ok = readGraphRoot(r, root, authoring, nodeList, pipeList, problem);
    if (!nodeList || !nodeList->isArray() || (pipeList && !pipeList->isArray()) ||
        problem != GraphJsonProblem::Content || (!ok && !authoring))
        return false;
    // Ids to indices: a lookup per pipe, not a scan (100000 nodes must load in seconds).
    std::unordered_map<std::string, int> index;
    for (std::size_t i = 0; i < nodeList->array.size() && (ok || authoring); ++i) {
        const std::string at = "$.nodes[" + std::to_string(i) + "]";
        GraphNode n;
        if (!readGraphNode(r, nodeList->array[i], at, authoring, n) ||
            (!authoring && !checkGraphNode(r, at, n))) {
            ok = false;
            continue;
        }
        const bool first = index.emplace(n.id, static_cast<int>(nodes.size())).second;
        if (!first && !authoring) ok = r.fail(at + ".id", "\"" + n.id + "\" is used twice");
        nodes.push_back(std::move(n));
    }
    const std::size_t pipeCount = pipeList ? pipeList->array.size() : 0;
    for (std::size_t i = 0; i < pipeCount && (ok || authoring); ++i) {
        const std::string at = "$.pipes[" + std::to_string(i) + "]";
        GraphPipe p;
        if (!readGraphPipe(r, pipeList->array[i], at, authoring, p)) {
            ok = false;
            continue;
        }
        if (const auto a = index.find(p.a); a != index.end()) p.nodeA = a->second;
        if (const auto b = index.find(p.b); b != index.end()) p.nodeB = b->second;
        if (!authoring && !checkGraphPipe(r, at, p, nodes)) {
            ok = false;
            continue;
        }
        pipes.push_back(std::move(p));
    }
    if (ok) problem = GraphJsonProblem::None;
    return ok;
}

namespace {

/// The manifest's header: a JSON object, a Plimsoll runtime bundle of this reader's major
/// schema version (any minor), and the body's name.
bool readManifestHeader(Reader& r, const std::string& text, const std::string& manifestPath,
                        Value& m, BundleManifest& out, std::string& error) {
    std::string parseError;
    if (!json::parse(text, m, parseError)) {
        error = manifestPath + ": malformed manifest: " + parseError;
        return false;
    }
    if (!m.isObject()) return r.fail("$", "malformed manifest: expected an object");
    const Value* formatName = m.find("format");
    if (!formatName || !formatName->isString() || formatName->string != format::kBundleFormat) {
        error = manifestPath + ": not a Plimsoll runtime bundle (\"format\" is not \"" +
                format::kBundleFormat + "\")";
        return false;
    }
    long long major = 0, minor = 0;
    if (!r.integer(m, "$", "schema_version", major) || !r.integer(m, "$", "schema_minor", minor))
        return false;
    out.schemaMajor = static_cast<int>(major);
    out.schemaMinor = static_cast<int>(minor);
    constexpr int kMajor = format::kBundleSchemaMajor;
    if (major != kMajor) {
        const std::string version = std::to_string(major) + "." + std::to_string(minor);
        error = manifestPath + ": bundle schema " + version +
                (major > kMajor ? " is newer than" : " is older than") + " this reader's " +
                std::to_string(kMajor) +
                ".x: export the bundle again with this version of plimsoll" +
                (major > kMajor ? " or update the runtime" : "");
        return false;
    }
    return r.string(m, "$", "body", out.body, false);
}

/// The manifest's `files`: each entry inside the bundle, listed once, its size >= 0.
bool readFileList(Reader& r, const Value& m, BundleManifest& out) {
    const Value* files = r.member(m, "$", "files");
    if (!files) return false;
    if (!files->isArray()) return r.fail("$.files", "expected an array");
    // Each file once: an entry repeated (or spelled again with "." or empty components) would
    // be read and hashed again for every listing, 2000 entries of one large file taking
    // minutes.
    std::unordered_map<std::string, std::size_t> firstListing;
    for (std::size_t i = 0; i < files->array.size(); ++i) {
        const Value& f = files->array[i];
        const std::string at = "$.files[" + std::to_string(i) + "]";
        if (!f.isObject()) return r.fail(at, "expected an object");
        std::string path, sha;
        long long bytes = 0;
        if (!r.string(f, at, "path", path) || !r.string(f, at, "sha256", sha) ||
            !r.integer(f, at, "bytes", bytes))
            return false;
        if (!staysInside(path))
            return r.fail(at + ".path",
                          "file path \"" + std::string(path.c_str()) + "\" leaves the bundle");
        if (const auto [first, added] = firstListing.emplace(normalPath(path), i); !added)
            return r.fail(at + ".path", "\"" + std::string(path.c_str()) +
                                            "\" is listed twice (also $.files[" +
                                            std::to_string(first->second) + "])");
        if (bytes < 0) return r.fail(at + ".bytes", "must be >= 0");
        out.files.push_back({std::move(path), std::move(sha), static_cast<std::uint64_t>(bytes)});
    }
    return true;
}

/// Every other path the manifest names (the water graph's, the painted maps'), inside the
/// bundle.
bool checkNamedPaths(Reader& r, const Value& m) {
    if (const Value* g = m.find("water_graph"); g && g->isObject()) {
        const Value* path = g->find("path");
        if (path && path->isString() && !staysInside(path->string))
            return r.fail("$.water_graph.path",
                          "\"" + std::string(path->string.c_str()) + "\" leaves the bundle");
    }
    if (const Value* maps = m.find("painted_maps"); maps && maps->isObject()) {
        for (const auto& [role, map] : maps->object) {
            const Value* path = map.isObject() ? map.find("path") : nullptr;
            if (path && path->isString() && !staysInside(path->string))
                return r.fail("$.painted_maps." + role + ".path",
                              "\"" + std::string(path->string.c_str()) + "\" leaves the bundle");
        }
    }
    return true;
}

/// The checks of a manifest's text (parseBundleManifest, and the first of every load), in
/// this order: its header, its file list, the other paths it names. `m` is the parsed
/// manifest.
bool checkManifest(const std::string& text, const std::string& manifestPath, Value& m,
                   BundleManifest& out, std::string& error) {
    Reader r(manifestPath, error);
    return readManifestHeader(r, text, manifestPath, m, out, error) && readFileList(r, m, out) &&
           checkNamedPaths(r, m);
}

/// A manifest as readManifest leaves it: the parsed JSON, what it says of the bundle, its own
/// size, and the verified bytes of the files the caller keeps.
struct ManifestRead {
    Value json;
    BundleManifest manifest;
    std::uint64_t manifestBytes = 0;
    std::map<std::string, std::string> kept;
};

/// The manifest read through `source` and checked whole (checkManifest) before any other
/// file is read; then, with `verify`, each listed file in the manifest's order with its size
/// and SHA-256, the bytes of those `keep` names (given the manifest and the path) kept in
/// `out.kept`. readBundleManifest, and the first step of every load.
bool readManifest(const BundleSource& source, bool verify,
                  const std::function<bool(const Value&, const std::string&)>& keep,
                  ManifestRead& out, std::string& error) {
    std::string text;
    if (!source.read(format::kManifestFile, kMaxJsonBytes, text, error)) return false;
    out.manifestBytes = text.size();
    const std::string manifestPath = source.name + "/" + format::kManifestFile;
    if (!checkManifest(text, manifestPath, out.json, out.manifest, error)) return false;
    if (!verify) return true;
    for (const BundleManifest::File& f : out.manifest.files) {
        const std::string full = source.name + "/" + f.path;
        std::string bytes;
        if (!source.read(f.path, kMaxFileBytes, bytes, error)) return false;
        if (bytes.size() != f.bytes) {
            error = full + ": " + std::to_string(bytes.size()) + " bytes, the manifest says " +
                    std::to_string(f.bytes) + " (truncated or replaced)";
            return false;
        }
        const std::string actual = sha256Hex(bytes.data(), bytes.size());
        if (actual != f.sha256) {
            error = full + ": SHA-256 " + actual + " does not match the manifest's " + f.sha256;
            return false;
        }
        if (keep && keep(out.json, f.path)) out.kept.emplace(f.path, std::move(bytes));
    }
    return true;
}

/// Whether the loader decodes `path` after verifying it, so that its verified bytes are kept:
/// the sample list, the texel-to-node map, and the graph and painted maps the manifest names.
bool decodedAfterVerifying(const Value& m, const std::string& path) {
    if (path == format::kSamplesFile || path == format::kTexelNodesFile) return true;
    const auto names = [&path](const Value* v) { return v && v->isString() && v->string == path; };
    if (const Value* g = m.find("water_graph"); g && g->isObject()) {
        if (names(g->find("path")) || names(g->find("texel_nodes"))) return true;
    }
    if (const Value* maps = m.find("painted_maps"); maps && maps->isObject()) {
        for (const auto& entry : maps->object) {
            if (entry.second.isObject() && names(entry.second.find("path"))) return true;
        }
    }
    return false;
}

}  // namespace

/// Loads one bundle into a Bundle in named steps, each of which returns false with the error
/// set: the manifest (readManifest: its checks, each listed file's size and checksum), the
/// body's facts, its sample lists and level ladder, and the water graph with the node and
/// permeability of each sample. Each file is read once, through the source, and what was
/// checked is what is decoded.
class BundleLoader {
public:
    BundleLoader(const BundleSource& source, Bundle& b, std::string& error, bool verify)
        : source_(source),
          b_(b),
          error_(error),
          verify_(verify),
          folder_(source.name),
          manifestPath_(source.name + "/" + format::kManifestFile),
          r_(manifestPath_, error) {}

    bool load() {
        b_.folder_ = folder_;
        return readHeader() && readBody() &&
               readSampleList(format::kSamplesFile, m_.find("sample_encoding"), "$.sample_encoding",
                              size_, count_, b_.samples_) &&
               readLevels() && readWaterGraph();
    }

private:
    /// The bytes of `relative` (kept until the load ends when they are to be decoded), or null
    /// with the error set.
    const std::string* read(const std::string& relative, std::uint64_t maxBytes) {
        const auto known = contents_.find(relative);
        if (known != contents_.end()) return &known->second;
        std::string bytes;
        if (!staysInside(relative)) {
            error_ = folder_ + "/" + relative + ": the path leaves the bundle";
            return nullptr;
        }
        if (!source_.read(relative, maxBytes, bytes, error_)) return nullptr;
        return &contents_.emplace(relative, std::move(bytes)).first->second;
    }

    /// The manifest's checks (readManifest: all of readBundleManifest), the bytes of the files
    /// decoded below kept from the checksum pass.
    bool readHeader() {
        ManifestRead read;
        if (!readManifest(source_, verify_, decodedAfterVerifying, read, error_)) return false;
        m_ = std::move(read.json);
        contents_ = std::move(read.kept);
        const BundleManifest& manifest = read.manifest;
        b_.schemaMajor_ = manifest.schemaMajor;
        b_.schemaMinor_ = manifest.schemaMinor;
        b_.body_ = manifest.body;
        b_.fileBytes_ = read.manifestBytes;
        for (const BundleManifest::File& f : manifest.files) {
            if (f.path == format::kTexelNodesFile) hasTexelNodes_ = true;
            listed_.push_back(f.path);
            b_.fileBytes_ += f.bytes;
        }
        return true;
    }

    /// The body's name, texture, UV placement, mass properties, hydrodynamic coefficients, the
    /// project's world and the radiation model.
    bool readBody() {
        if (!r_.integer(m_, "$", "texture_size", size_) ||
            !r_.integer(m_, "$", "texel_samples", count_))
            return false;
        if (size_ < 1 || size_ > kMaxTextureSide)
            return r_.fail("$.texture_size", "out of range 1.." + std::to_string(kMaxTextureSide));
        // A texel holds a few entries (UV islands sharing it, refinement): 4 per texel at most.
        if (count_ < 0 || count_ > 4 * size_ * size_)
            return r_.fail("$.texel_samples", "must be in 0..4 x texture_size^2");
        b_.textureSize_ = static_cast<int>(size_);
        if (!readUvPlacement()) return false;
        const Value* massProps = r_.member(m_, "$", "mass_properties");
        if (!massProps) return false;
        const Value* texture = r_.member(*massProps, "$.mass_properties", "texture");
        if (!texture || !readMass(r_, *texture, "$.mass_properties.texture", b_.mass_))
            return false;
        if (!readHydrodynamics()) return false;
        // The project's world (1.4): the fluid's density and gravity are the project's.
        if (!readBundleWorld(m_, manifestPath_, b_.world_, error_)) return false;
        b_.fluid_.density = b_.world_.density;
        b_.fluid_.gravity = norm(b_.world_.gravity);
        if (const Value* radiation = m_.find("radiation"); radiation && !radiation->isNull()) {
            auto model = std::make_unique<Radiation>();
            if (!readRadiation(r_, *radiation, "$.radiation", *model)) return false;
            b_.radiation_ = std::move(model);
        }
        return true;
    }

    bool readUvPlacement() {
        const Value* placement = r_.member(m_, "$", "uv_placement");
        if (!placement) return false;
        if (!r_.number(*placement, "$.uv_placement", "scale", uvScale_)) return false;
        const Value* offset = r_.member(*placement, "$.uv_placement", "offset");
        if (!offset) return false;
        if (!offset->isArray() || offset->array.size() != 2 || !offset->array[0].isNumber() ||
            !offset->array[1].isNumber())
            return r_.fail("$.uv_placement.offset", "expected an array of 2 numbers");
        uvOffset_ = {offset->array[0].number, offset->array[1].number, 0};
        if (!(uvScale_ > 0) || !std::isfinite(uvScale_))
            return r_.fail("$.uv_placement.scale", "must be finite and > 0");
        if (!finite(uvOffset_)) return r_.fail("$.uv_placement.offset", "must be finite");
        return true;
    }

    bool readHydrodynamics() {
        const Value* hydro = m_.find("hydrodynamics");
        if (!hydro) return true;
        const std::string at = "$.hydrodynamics";
        if (!r_.number(*hydro, at, "drag_coefficient", b_.fluid_.dragCoefficient, false) ||
            !r_.number(*hydro, at, "friction_coefficient", b_.fluid_.frictionCoefficient, false) ||
            !r_.number(*hydro, at, "linear_damping", b_.linearDamping_, false) ||
            !r_.number(*hydro, at, "angular_damping", b_.angularDamping_, false))
            return false;
        // Absent (every body without radiation, and bundles before it): as the horizontal.
        b_.verticalDamping_ = b_.linearDamping_;
        if (!r_.number(*hydro, at, "vertical_damping", b_.verticalDamping_, false)) return false;
        for (const double v : {b_.fluid_.dragCoefficient, b_.fluid_.frictionCoefficient,
                               b_.linearDamping_, b_.verticalDamping_, b_.angularDamping_}) {
            if (!(v >= 0) || !std::isfinite(v))
                return r_.fail(at, "coefficients and damping must be finite and >= 0");
        }
        return true;
    }

    /// The compact encoding's origin and scales; compact stays false for plain float samples.
    bool readSampleEncoding(const Value* encoding, const std::string& at, bool& compact,
                            Vec3& origin, double& positionScale, double& areaScale) {
        if (!encoding || encoding->isNull()) return true;
        std::string type;
        if (!encoding->isObject()) return r_.fail(at, "expected an object or null");
        if (!r_.string(*encoding, at, "type", type)) return false;
        if (type != format::kCompactSampleEncoding)
            return r_.fail(at + ".type", "unknown sample encoding \"" + std::string(type.c_str()) +
                                             "\" (this runtime knows " +
                                             format::kCompactSampleEncoding + ")");
        if (!r_.vec3(*encoding, at, "position_origin", origin) ||
            !r_.number(*encoding, at, "position_scale", positionScale) ||
            !r_.number(*encoding, at, "area_scale", areaScale))
            return false;
        if (!finite(origin)) return r_.fail(at + ".position_origin", "must be finite");
        for (const auto& [key, scale] :
             {std::pair{"position_scale", positionScale}, std::pair{"area_scale", areaScale}}) {
            if (!(scale > 0) || !std::isfinite(scale))
                return r_.fail(at + "." + key, "must be finite and > 0");
        }
        compact = true;
        return true;
    }

    /// A sample list (bake_io.cpp's layout: channels x y px py pz ax ay az area coverage), or
    /// its compact encoding (sample_encoding: half floats over an origin and two scales): the
    /// body's samples.exr and each coarser level's.
    bool readSampleList(const std::string& file, const Value* encoding, const std::string& at,
                        long long size, long long count, std::vector<Sample>& out) {
        static const std::vector<std::string> kChannels = {"x",  "y",  "px", "py",   "pz",
                                                           "ax", "ay", "az", "area", "coverage"};
        static const std::vector<std::string> kCompactChannels(
            std::begin(format::kCompactSampleChannels), std::end(format::kCompactSampleChannels));
        const std::string samplesPath = folder_ + "/" + file;
        bool compact = false;
        Vec3 origin;
        double positionScale = 1, areaScale = 1;
        if (!readSampleEncoding(encoding, at, compact, origin, positionScale, areaScale))
            return false;
        const std::string* samplesBytes = read(file, kMaxFileBytes);
        if (!samplesBytes) return false;
        int width = 0, height = 0;
        std::vector<float> px;
        // The exporter's layout: rows of a fixed width, as many as the samples need (one spare).
        const std::uint64_t samplePixels = static_cast<std::uint64_t>(count) + 2 * 8192;
        std::vector<bool> half;
        if (compact) {
            half.assign(kCompactChannels.size(), true);
            half[0] = half[1] = false;  // texel indices: float32
        }
        if (!readExrFloat(samplesPath, *samplesBytes, compact ? kCompactChannels : kChannels, half,
                          samplePixels, width, height, px, error_))
            return false;
        if (static_cast<std::size_t>(count) > static_cast<std::size_t>(width) * height) {
            error_ = samplesPath + ": holds fewer samples than the manifest's texel_samples (" +
                     std::to_string(count) + ")";
            return false;
        }
        out.resize(static_cast<std::size_t>(count));
        for (std::size_t i = 0; i < out.size(); ++i) {
            const float* in = &px[i * kChannels.size()];
            const int x = static_cast<int>(in[0]), y = static_cast<int>(in[1]);
            if (x < 0 || y < 0 || x >= size || y >= size || !(in[9] > 0.0f)) {
                error_ = samplesPath + ": sample " + std::to_string(i) +
                         " is not a covered texel of the texture";
                return false;
            }
            Sample& s = out[i];
            s.texel = static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(size) +
                      static_cast<std::uint32_t>(x);
            if (compact) {
                // A NaN or infinite half would pass through the scales as one: named as such.
                for (int k = 2; k < 10; ++k) {
                    if (!std::isfinite(in[k])) {
                        error_ = samplesPath + ": sample " + std::to_string(i) +
                                 " holds a NaN or infinite half in '" + kCompactChannels[k] + "'";
                        return false;
                    }
                }
                const Vec3 q{in[2], in[3], in[4]}, a{in[5], in[6], in[7]};
                s.position = origin + positionScale * q;
                s.areaVector = areaScale * a;
                s.area = areaScale * in[8];
            } else {
                s.position = {in[2], in[3], in[4]};
                s.areaVector = {in[5], in[6], in[7]};
                s.area = in[8];
            }
            s.coverage = in[9];
            // NaN, Inf or a negative area would turn every force into garbage, silently.
            if (!finite(s.position) || !finite(s.areaVector) || !std::isfinite(s.area) ||
                !(s.area >= 0) || !std::isfinite(s.coverage) || s.coverage > 1.0f + 1e-6f) {
                error_ = samplesPath + ": sample " + std::to_string(i) +
                         " has a non-finite position or area vector, a negative area or a "
                         "coverage outside 0..1";
                return false;
            }
        }
        return true;
    }

    /// The level ladder (1.6): coarsest first, the finest the body's own samples.exr. Without
    /// one, the body has one level.
    bool readLevels() {
        b_.levels_ = {BundleLevel{b_.textureSize_, b_.samples_.size(), 0, 0, 0}};
        const Value* levels = m_.find("levels");
        if (!levels || levels->isNull()) return true;
        const std::string at = "$.levels";
        if (!levels->isArray() || levels->array.size() < 2 || levels->array.size() > kMaxLevels)
            return r_.fail(
                at, "expected null or an array of 2.." + std::to_string(kMaxLevels) + " levels");
        b_.levels_.clear();
        for (std::size_t k = 0; k < levels->array.size(); ++k) {
            if (!readLevel(levels->array[k], at + "[" + std::to_string(k) + "]",
                           k + 1 == levels->array.size()))
                return false;
        }
        return true;
    }

    bool readLevel(const Value& v, const std::string& here, bool finest) {
        if (!v.isObject()) return r_.fail(here, "expected an object");
        BundleLevel level;
        long long levelSize = 0, levelCount = 0;
        std::string file;
        if (!r_.integer(v, here, "size", levelSize) ||
            !r_.integer(v, here, "texel_samples", levelCount) ||
            !r_.string(v, here, "samples", file) ||
            !r_.number(v, here, "force_error", level.forceError) ||
            !r_.number(v, here, "torque_error", level.torqueError) ||
            !r_.number(v, here, "evaluation_us", level.evaluationUs))
            return false;
        if (!(level.forceError >= 0) || !(level.torqueError >= 0) || !(level.evaluationUs >= 0))
            return r_.fail(here, "errors and cost must be >= 0");
        const long long below = b_.levels_.empty() ? 0 : b_.levels_.back().size;
        if (levelSize <= below || levelSize > size_ || (finest && levelSize != size_) ||
            (!finest && levelSize == size_))
            return r_.fail(here + ".size", "sizes must ascend to texture_size, the finest's");
        if (levelCount < 0 || levelCount > 4 * levelSize * levelSize)
            return r_.fail(here + ".texel_samples", "must be in 0..4 x size^2");
        level.size = static_cast<int>(levelSize);
        level.samples = static_cast<std::size_t>(levelCount);
        if (finest) {
            if (file != format::kSamplesFile || level.samples != b_.samples_.size())
                return r_.fail(here,
                               "the finest level must be samples.exr with texel_samples entries");
        } else {
            if (!staysInside(file)) return r_.fail(here + ".samples", "the path leaves the bundle");
            auto coarse = std::make_unique<Bundle::CoarseLevel>();
            if (!readSampleList(file, v.find("sample_encoding"), here + ".sample_encoding",
                                levelSize, levelCount, coarse->samples))
                return false;
            b_.coarse_.push_back(std::move(coarse));
        }
        b_.levels_.push_back(level);
        return true;
    }

    /// The water graph: its settings, nodes and pipes, the node each sample feeds and the
    /// permeable samples as exchange points.
    bool readWaterGraph() {
        const Value* graphInfo = m_.find("water_graph");
        if (!graphInfo || graphInfo->isNull()) return true;
        const std::string at = "$.water_graph";
        if (!graphInfo->isObject()) return r_.fail(at, "expected an object or null");
        auto graph = std::make_unique<GraphLayout>();
        std::string graphFile;
        if (!readGraphSettings(*graphInfo, graph->settings_, graphFile)) return false;
        const std::string* graphText = read(graphFile, kMaxJsonBytes);
        if (!graphText) return false;
        GraphJsonProblem problem = GraphJsonProblem::None;
        if (!readGraphJson(folder_ + "/" + graphFile, *graphText, GraphJsonMode::Bundle,
                           graph->nodes_, graph->pipes_, problem, error_))
            return false;
        std::vector<std::uint32_t> texelNodes;
        std::string texelNodesFile;
        if (!readTexelNodes(*graphInfo, texelNodes, texelNodesFile) ||
            !assignSampleNodes(*graph, texelNodes, texelNodesFile))
            return false;
        std::vector<GraphLayout::Exchange> exchange;
        if (!readExchangePoints(*graph, exchange)) return false;
        graph->prepare(std::move(exchange));
        b_.graph_ = std::move(graph);
        return true;
    }

    /// The manifest's `water_graph`: the graph's file, the simulation's models and the scale of
    /// the permeability map (permeability_, which readExchangePoints applies).
    bool readGraphSettings(const Value& info, GraphSettings& gs, std::string& graphFile) {
        const std::string at = "$.water_graph";
        std::string inflow = plimsoll_eval::inflowModelName(gs.inflow),
                    flow = plimsoll_eval::flowModelName(gs.flow);
        double seed = 1;
        if (!r_.string(info, at, "path", graphFile) ||
            !r_.number(info, at, "permeability", permeability_, false) ||
            !r_.string(info, at, "inflow", inflow, false) ||
            !r_.number(info, at, "inflow_rate", gs.inflowRate, false) ||
            !r_.number(info, at, "discharge_coefficient", gs.dischargeCoefficient, false) ||
            !r_.string(info, at, "flow", flow, false) ||
            !r_.number(info, at, "diffusion_pressure", gs.diffusionPressure, false) ||
            !r_.boolean(info, at, "free_surface", gs.freeSurface, false) ||
            !r_.number(info, at, "seed", seed, false))
            return false;
        if (!plimsoll_eval::inflowModelFromName(inflow, gs.inflow))
            return r_.fail(at + ".inflow", "unknown inflow model \"" + inflow + "\"");
        if (!plimsoll_eval::flowModeFromName(flow, gs.flow))
            return r_.fail(at + ".flow", "unknown flow model \"" + flow + "\"");
        if (!(seed >= 0) || !(seed <= 9.0e15))
            return r_.fail(at + ".seed", "must be an integer in 0..9e15");
        for (const double v :
             {permeability_, gs.inflowRate, gs.dischargeCoefficient, gs.diffusionPressure}) {
            if (!(v >= 0) || !std::isfinite(v))
                return r_.fail(at,
                               "permeability, inflow_rate, discharge_coefficient and "
                               "diffusion_pressure must be finite and >= 0");
        }
        gs.seed = static_cast<std::uint64_t>(seed);
        if (!staysInside(graphFile))
            return r_.fail(at + ".path",
                           "\"" + std::string(graphFile.c_str()) + "\" leaves the bundle");
        return true;
    }

    /// texel_nodes.exr where the bundle has it (1.1 names the file in water_graph.texel_nodes;
    /// it is also listed in `files`): the node of each texel, 1-based, 0 for none.
    bool readTexelNodes(const Value& info, std::vector<std::uint32_t>& texelNodes,
                        std::string& file) {
        const std::string at = "$.water_graph";
        file = hasTexelNodes_ ? format::kTexelNodesFile : "";
        if (!r_.string(info, at, "texel_nodes", file, false)) return false;
        if (file.empty()) return true;
        if (std::find(listed_.begin(), listed_.end(), file) == listed_.end())
            return r_.fail(at + ".texel_nodes", "\"" + file + "\" is not in the manifest's files");
        const std::string path = folder_ + "/" + file;
        int w = 0, h = 0;
        const std::string* nodesBytes = read(file, kMaxFileBytes);
        if (!nodesBytes) return false;
        if (!readExrUint(path, *nodesBytes, "node", static_cast<std::uint64_t>(size_) * size_, w, h,
                         texelNodes, error_))
            return false;
        if (w != size_ || h != size_) {
            error_ = path + ": " + std::to_string(w) + " x " + std::to_string(h) +
                     ", the texture is " + std::to_string(size_) + " x " + std::to_string(size_);
            return false;
        }
        b_.texelNodesFromFile_ = true;
        return true;
    }

    /// The node each sample feeds: the texel-to-node map for texels with one entry (the map
    /// has one value per texel); the engine's rule, from the code the engine runs, for the rest.
    bool assignSampleNodes(GraphLayout& graph, const std::vector<std::uint32_t>& texelNodes,
                           const std::string& texelNodesFile) {
        const std::size_t nodeCount = graph.nodes_.size();
        std::vector<plimsoll_eval::NodeShape> shapes;
        for (const GraphNode& n : graph.nodes_)
            shapes.push_back(
                {{n.position.x, n.position.y, n.position.z}, {n.box.x, n.box.y, n.box.z}});
        const plimsoll_eval::NearestNodeIndex nearest(std::move(shapes));
        const std::vector<Sample>& samples = b_.samples_;
        graph.sampleNodes_.resize(samples.size());
        for (std::size_t i = 0; i < samples.size(); ++i) {
            const Sample& s = samples[i];
            const bool shared = (i > 0 && samples[i - 1].texel == s.texel) ||
                                (i + 1 < samples.size() && samples[i + 1].texel == s.texel);
            int node = -1;
            if (!texelNodes.empty() && !shared) {
                const auto size = static_cast<std::uint32_t>(size_);
                const std::uint32_t x = s.texel % size, y = s.texel / size;
                const std::uint32_t v =
                    texelNodes[(static_cast<std::size_t>(size) - 1 - y) * size + x];
                if (v == 0 || v > nodeCount) {
                    error_ = folder_ + "/" + texelNodesFile + ": texel (" + std::to_string(x) +
                             ", " + std::to_string(y) + ") is covered but maps to " +
                             std::to_string(v) + " (expected 1.." + std::to_string(nodeCount) + ")";
                    return false;
                }
                node = static_cast<int>(v) - 1;
            } else {
                node = nearest.nearest({s.position.x, s.position.y, s.position.z});
            }
            graph.sampleNodes_[i] = node;
        }
        return true;
    }

    /// Permeability per sample: the painted map at the texel centre, as the engine's
    /// sampleAtTexels (bilinear, clamped), times the project's scale. The samples it lets
    /// water through, feeding an unsealed node, are the exchange points.
    bool readExchangePoints(const GraphLayout& graph,
                            std::vector<GraphLayout::Exchange>& exchange) {
        const Value* maps = m_.find("painted_maps");
        const Value* perm = maps ? maps->find("permeability") : nullptr;
        if (!perm || perm->isNull()) return true;
        std::string mapFile;
        if (!r_.string(*perm, "$.painted_maps.permeability", "path", mapFile)) return false;
        if (!staysInside(mapFile))
            return r_.fail("$.painted_maps.permeability.path",
                           "\"" + std::string(mapFile.c_str()) + "\" leaves the bundle");
        const std::string* bytes = read(mapFile, kMaxFileBytes);
        if (!bytes) return false;
        std::string pngError;
        GreyImage map;
        if (!decodePng(*bytes, map, pngError)) {
            error_ = folder_ + "/" + mapFile + ": cannot read painted map: " + pngError;
            return false;
        }
        const double n = static_cast<double>(size_);
        for (std::size_t i = 0; i < b_.samples_.size(); ++i) {
            const std::uint32_t texel = b_.samples_[i].texel;
            const double tu = (texel % size_ + 0.5) / n, tv = (texel / size_ + 0.5) / n;
            const double u = (tu - uvOffset_.x) / uvScale_, v = (tv - uvOffset_.y) / uvScale_;
            const double k = std::clamp(permeability_ * bilinear(map, u, v), 0.0, 1.0);
            if (!(k > 0)) continue;
            const int node = graph.sampleNodes_[i];
            if (node < 0 || graph.nodes_[node].sealed) continue;
            exchange.push_back({b_.samples_[i].position, k * b_.samples_[i].area,
                                static_cast<std::uint32_t>(node)});
        }
        return true;
    }

    /// The map's value at (u, v), bilinear between pixel centres and clamped at the edges.
    static double bilinear(const GreyImage& map, double u, double v) {
        const double fx = std::clamp(u * map.width - 0.5, 0.0, map.width - 1.0);
        const double fy = std::clamp((1.0 - v) * map.height - 0.5, 0.0, map.height - 1.0);
        const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
        const int x1 = std::min(x0 + 1, map.width - 1), y1 = std::min(y0 + 1, map.height - 1);
        const double ax = fx - x0, ay = fy - y0;
        auto at = [&](int px, int py) {
            return static_cast<double>(map.values[static_cast<std::size_t>(py) * map.width + px]);
        };
        return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) +
               ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
    }

    const BundleSource& source_;
    Bundle& b_;
    std::string& error_;
    const bool verify_;
    const std::string folder_, manifestPath_;
    Reader r_;
    Value m_;
    std::map<std::string, std::string> contents_;  ///< bytes read, kept while decoded
    std::vector<std::string> listed_;              ///< the manifest's files
    bool hasTexelNodes_ = false;
    long long size_ = 0, count_ = 0;  ///< texture_size, texel_samples
    double uvScale_ = 1;
    Vec3 uvOffset_;
    double permeability_ = 1;  ///< water_graph.permeability: the scale of the permeability map
};

namespace {

std::unique_ptr<Bundle> loadFrom(const BundleSource& source, std::string& error,
                                 const LoadOptions& options) {
    auto bundle = std::make_unique<Bundle>();
    error.clear();
    try {
        if (!BundleLoader(source, *bundle, error, options.verifyChecksums).load()) return nullptr;
    } catch (const std::exception& e) {
        error = source.name + ": " + e.what();
        return nullptr;
    }
    return bundle;
}

}  // namespace

namespace {

/// The folder's identity (device and inode), or none when it cannot be looked at.
std::optional<std::pair<dev_t, ino_t>> folderIdentity(const std::string& folder) {
    struct stat st {};
    if (::stat(folder.c_str(), &st) != 0) return std::nullopt;
    return std::pair{st.st_dev, st.st_ino};
}

}  // namespace

std::unique_ptr<Bundle> loadBundle(const std::string& folder, std::string& error,
                                   const LoadOptions& options) {
    // A re-export replaces the folder in one rename and then deletes the old one: a load that
    // began on the old folder can find its files gone. Such a load starts again on the new
    // folder (a few times at most: a bundle re-exported without pause is a caller's loop).
    for (int attempt = 0;; ++attempt) {
        const auto before = folderIdentity(folder);
        std::unique_ptr<Bundle> bundle = loadFrom(folderSource(folder), error, options);
        if (bundle || attempt == 3 || !before || folderIdentity(folder) == before) return bundle;
    }
}

std::unique_ptr<Bundle> loadBundleWithCallbacks(const FileCallbacks& callbacks,
                                                const std::string& name, std::string& error,
                                                const LoadOptions& options) {
    if (!callbacks.open || !callbacks.size || !callbacks.read || !callbacks.close) {
        error = name + ": the file callbacks need open, size, read and close";
        return nullptr;
    }
    return loadFrom(callbackSource(callbacks, name), error, options);
}

std::unique_ptr<Bundle> loadBundleFromMemory(const std::vector<MemoryFile>& files,
                                             const std::string& name, std::string& error,
                                             const LoadOptions& options) {
    // The list itself is checked first: a path that leaves the bundle or comes twice is the
    // caller's mistake, named before any file is looked at.
    std::map<std::string, const MemoryFile*> byPath;
    for (std::size_t i = 0; i < files.size(); ++i) {
        const MemoryFile& f = files[i];
        const std::string at = name + ": memory file " + std::to_string(i) + " (\"" +
                               std::string(f.path.c_str()) + "\")";
        if (!staysInside(f.path)) {
            error = at + ": the path leaves the bundle";
            return nullptr;
        }
        if (!f.data && f.size > 0) {
            error = at + ": no bytes (data is null)";
            return nullptr;
        }
        if (!byPath.emplace(f.path, &f).second) {
            error = at + ": the path comes twice";
            return nullptr;
        }
    }
    struct Cursor {
        const MemoryFile* file;
    };
    FileCallbacks callbacks;
    callbacks.open = [&byPath](const std::string& path) -> void* {
        const auto found = byPath.find(path);
        return found == byPath.end() ? nullptr : new Cursor{found->second};
    };
    callbacks.size = [](void* c) {
        return static_cast<long long>(static_cast<Cursor*>(c)->file->size);
    };
    callbacks.read = [](void* c, std::uint64_t offset, void* buffer,
                        std::size_t bytes) -> long long {
        const MemoryFile& f = *static_cast<Cursor*>(c)->file;
        if (offset >= f.size) return 0;
        const std::size_t n = std::min<std::uint64_t>(bytes, f.size - offset);
        std::memcpy(buffer, static_cast<const char*>(f.data) + offset, n);
        return static_cast<long long>(n);
    };
    callbacks.close = [](void* c) { delete static_cast<Cursor*>(c); };
    return loadFrom(callbackSource(callbacks, name), error, options);
}

bool readBundleManifest(const std::string& folder, BundleManifest& out, std::string& error,
                        bool verifyFiles) {
    const BundleSource source = folderSource(folder);
    ManifestRead read;
    try {
        if (!readManifest(source, verifyFiles, nullptr, read, error)) return false;
    } catch (const std::exception& e) {
        error = source.name + ": " + e.what();
        return false;
    }
    out = std::move(read.manifest);
    return true;
}

bool parseBundleManifest(const std::string& text, const std::string& manifestName,
                         BundleManifest& out, std::string& error) {
    Value m;
    BundleManifest manifest;
    try {
        if (!checkManifest(text, manifestName, m, manifest, error)) return false;
    } catch (const std::exception& e) {
        error = manifestName + ": " + e.what();
        return false;
    }
    out = std::move(manifest);
    return true;
}

std::uint64_t Bundle::memoryBytes() const {
    std::uint64_t bytes = sizeof(Bundle) + samples_.capacity() * sizeof(Sample);
    if (graph_) bytes += graph_->memoryBytes();
    if (radiation_) {
        bytes += sizeof(Radiation);
        for (const auto& terms : radiation_->memory)
            bytes += terms.capacity() * sizeof(RadiationTerm);
    }
    return bytes + fastBytes();
}

Version bundleSchemaVersion() {
    return {format::kBundleSchemaMajor, format::kBundleSchemaMinor, 0};
}

Version runtimeVersion() {
    return {PLIMSOLL_RUNTIME_VERSION_MAJOR, PLIMSOLL_RUNTIME_VERSION_MINOR,
            PLIMSOLL_RUNTIME_VERSION_PATCH};
}

}  // namespace plimsoll_runtime
