// Physics solids worked out on workers (physics_solids.h).
#include "document/physics_solids.h"

#include "document/physics_bakes.h"

#include <atomic>
#include <chrono>
#include <thread>

namespace plimsoll::editor {

struct PhysicsSolids::Job {
    std::atomic<bool> done{false};
    Solid result;
};

namespace {

/// The cap triangles of every opening as a mesh of their own.
std::shared_ptr<const TriangleMesh> capsOf(const PreparedBodyMesh& prepared) {
    if (prepared.openings.empty()) return nullptr;
    auto caps = std::make_shared<TriangleMesh>();
    caps->source = prepared.mesh.source + " (caps)";
    caps->positions = prepared.mesh.positions;
    for (const Opening& opening : prepared.openings)
        for (std::uint32_t t : opening.capTriangles)
            caps->triangles.push_back(prepared.mesh.triangles[t]);
    return caps;
}

}  // namespace

PhysicsSolids::Solid PhysicsSolids::solidFor(const Document& document, std::size_t body) {
    BodyState& state = bodies_[body];
    if (body >= document.bodyCount()) return {};
    const BodyAssets& assets = document.assets(body);
    const BodyDesc& desc = document.project().bodies[body];
    if (!assets.mesh || desc.deforms()) return {};
    Key key;
    key.mesh = assets.mesh.get();
    key.closeOpenings = desc.openings != OpeningsMode::None;
    for (const CapDesc& cap : desc.caps) key.heights.push_back(cap.height);
    if (state.key != key) {
        state.key = key;
        auto job = std::make_shared<Job>();
        state.job = job;
        state.solid.working = true;
        std::thread([job, project = document.project(), mesh = assets.mesh, body] {
            lowerThisThreadsPriority();
            Result<PreparedBodyMesh> prepared =
                prepareLoadedBodyMesh(project, body, *mesh, /*uvsChosen=*/true);
            if (prepared) {
                auto shared = std::make_shared<const PreparedBodyMesh>(std::move(*prepared));
                job->result.prepared = shared;
                if (!shared->repairs.empty())
                    job->result.solid = std::shared_ptr<const TriangleMesh>(shared, &shared->mesh);
                job->result.caps = capsOf(*shared);
            } else {
                job->result.error = prepared.error().message;
            }
            job->done.store(true, std::memory_order_release);
        }).detach();
    }
    return state.solid;
}

bool PhysicsSolids::poll() {
    bool arrived = false;
    for (auto& [body, state] : bodies_) {
        if (!state.job || !state.job->done.load(std::memory_order_acquire)) continue;
        Solid result = std::move(state.job->result);
        state.job.reset();
        if (result.prepared || !result.error.empty()) {
            state.solid = std::move(result);
        }
        state.solid.working = false;
        arrived = true;
    }
    return arrived;
}

void PhysicsSolids::wait() {
    for (auto& [body, state] : bodies_)
        while (state.job && !state.job->done.load(std::memory_order_acquire))
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
    poll();
}

}  // namespace plimsoll::editor
