// One floating body over a shared bundle (runtime.hpp, Body): its water graph's state and its
// radiation memory, and their snapshot.
#include "plimsoll_runtime/runtime.hpp"

#include "bytes.hpp"

#include <cmath>

namespace plimsoll_runtime {

namespace {
constexpr std::uint64_t kBodySnapshotMagic = 0x3259444F42534C50ull;  // "PLSBODY2"
}  // namespace

Body::Body(const Bundle& bundle) : bundle_(&bundle) {
    if (const GraphLayout* layout = bundle.graph()) graph_ = std::make_unique<WaterGraph>(*layout);
    if (const Radiation* radiation = bundle.radiation())
        radiation_ = std::make_unique<RadiationMemory>(radiation);
}

Body::Body(const Body& other) : bundle_(other.bundle_), sleep_(other.sleep_) {
    if (other.graph_) graph_ = std::make_unique<WaterGraph>(*other.graph_);
    if (other.radiation_) radiation_ = std::make_unique<RadiationMemory>(*other.radiation_);
}

Body::~Body() = default;

std::vector<std::uint8_t> Body::save() const {
    std::vector<std::uint8_t> out;
    save(out);
    return out;
}

void Body::save(std::vector<std::uint8_t>& out) const {
    out.clear();
    putBytes(out, kBodySnapshotMagic);
    putBytes(out, static_cast<std::uint64_t>(bundle_->samples().size()));
    putBytes(out, static_cast<std::uint8_t>((graph_ ? 1 : 0) | (radiation_ ? 2 : 0)));
    if (graph_) graph_->saveState(out);
    if (radiation_) radiation_->saveState(out);
    putBytes(out, static_cast<std::uint8_t>(sleep_.asleep ? 1 : 0));
    for (double v :
         {sleep_.restedFor, sleep_.waterHeight, sleep_.pose.position.x, sleep_.pose.position.y,
          sleep_.pose.position.z, sleep_.pose.orientation.w, sleep_.pose.orientation.x,
          sleep_.pose.orientation.y, sleep_.pose.orientation.z})
        putBytes(out, v);
}

void Body::wake() {
    sleep_.asleep = false;
    sleep_.restedFor = 0;
}

bool Body::restore(const std::vector<std::uint8_t>& bytes, std::string& error) {
    std::size_t at = 0;
    std::uint64_t magic = 0, samples = 0;
    std::uint8_t parts = 0;
    if (!takeBytes(bytes, at, magic) || !takeBytes(bytes, at, samples) ||
        !takeBytes(bytes, at, parts) || magic != kBodySnapshotMagic ||
        samples != bundle_->samples().size() ||
        parts != ((graph_ ? 1 : 0) | (radiation_ ? 2 : 0))) {
        error = "snapshot: not a snapshot of a body of " + bundle_->folder();
        return false;
    }
    // Into copies first: a snapshot that fails halfway changes nothing.
    std::unique_ptr<WaterGraph> graph = graph_ ? std::make_unique<WaterGraph>(*graph_) : nullptr;
    std::unique_ptr<RadiationMemory> radiation =
        radiation_ ? std::make_unique<RadiationMemory>(*radiation_) : nullptr;
    if (graph && !graph->restoreState(bytes, at)) {
        error = "snapshot: the water graph's state does not fit this body";
        return false;
    }
    if (radiation && !radiation->restoreState(bytes, at)) {
        error = "snapshot: the radiation memory does not fit this body";
        return false;
    }
    Sleep sleep;
    std::uint8_t asleep = 0;
    double v[9];
    bool read = takeBytes(bytes, at, asleep) && asleep <= 1;
    for (double& d : v) read = read && takeBytes(bytes, at, d) && std::isfinite(d);
    if (!read) {
        error = "snapshot: the sleep state is truncated or not finite";
        return false;
    }
    sleep.asleep = asleep == 1;
    sleep.restedFor = v[0];
    sleep.waterHeight = v[1];
    sleep.pose.position = {v[2], v[3], v[4]};
    sleep.pose.orientation = {v[5], v[6], v[7], v[8]};
    if (at != bytes.size()) {
        error = "snapshot: " + std::to_string(bytes.size() - at) + " bytes too many";
        return false;
    }
    graph_ = std::move(graph);
    radiation_ = std::move(radiation);
    sleep_ = sleep;
    return true;
}

std::uint64_t Body::stateHash() const { return fnv1a(save()); }

std::uint64_t Body::memoryBytes() const {
    std::uint64_t bytes = sizeof(Body);
    if (graph_) bytes += graph_->memoryBytes();
    if (radiation_) {
        // The filters' heap is what their snapshot holds, to a few bytes.
        bytes += sizeof(RadiationMemory);
        std::vector<std::uint8_t> filters;
        radiation_->saveState(filters);
        bytes += filters.size();
    }
    return bytes;
}

}  // namespace plimsoll_runtime
