#include "document/physics_bakes.h"

#include "plimsoll/bake/cancellable_bake.h"
#include "plimsoll/scene/level_ladder.h"

#include <atomic>

#include <sys/resource.h>
#include <unistd.h>

namespace plimsoll::editor {

void lowerThisThreadsPriority() {
#if defined(__linux__)
    (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), 10);
#endif
}

/// One bake on its own thread. The thread writes `result` and then sets `done`; the UI reads
/// `result` only after seeing `done`.
struct PhysicsBakes::Job {
    std::shared_ptr<const TriangleMesh> mesh;
    BakeSettings settings;
    int previousSize = 0;
    std::atomic<bool> cancel{false};
    std::atomic<double> progress{0.0};
    std::atomic<bool> done{false};
    std::optional<Result<SurfaceTextures>> result;
    /// A body that gives a tolerance (settings.size 0): the pick of its size, whose bake is
    /// `result`.
    std::optional<double> tolerance;
    std::optional<LevelChoice> choice;
    std::thread thread;
    ~Job() {
        cancel = true;
        if (thread.joinable()) thread.join();
    }
};

namespace {

bool sameSettings(const BakeSettings& a, const BakeSettings& b) {
    return a.size == b.size && a.maxTexelStretch == b.maxTexelStretch;
}

}  // namespace

PhysicsBakes::~PhysicsBakes() {
    for (auto& [body, state] : bodies_) {
        if (state.job) state.job->cancel = true;
    }
    for (auto& job : abandoned_) job->cancel = true;
    // The jobs' destructors join their threads, each stopping within a band of rows.
}

std::shared_ptr<const SurfaceTextures> PhysicsBakes::texturesFor(Document& document,
                                                                 std::size_t body) {
    reapAbandoned();
    if (body >= document.bodyCount()) return nullptr;
    BodyState& state = bodies_[body];
    const std::shared_ptr<const TriangleMesh>& mesh = document.assets(body).mesh;
    const BakeSettings settings = document.physicsBakeSettings(body);
    if (auto baked = document.bakedPhysics(body)) {
        if (state.textures != baked) {
            state.mesh = mesh;
            state.settings = settings;
            state.textures = baked;
        }
        return baked;
    }
    if (!mesh) return nullptr;
    // Back to the size it had (undo, Cancel): those textures again, with no bake.
    if (state.textures && state.mesh == mesh && sameSettings(state.settings, settings) &&
        document.adoptPhysics(body, mesh.get(), settings, state.textures)) {
        if (state.job) abandon(state);
        return state.textures;
    }
    const bool jobFits =
        state.job && state.job->mesh == mesh && sameSettings(state.job->settings, settings);
    const bool failedBefore = state.failedSettings && state.failedMesh == mesh.get() &&
                              sameSettings(*state.failedSettings, settings);
    if (!jobFits && !failedBefore) {
        if (state.job) abandon(state);
        state.failedSettings.reset();
        state.error.clear();
        auto job = std::make_shared<Job>();
        job->mesh = mesh;
        job->settings = settings;
        job->previousSize = state.textures && state.mesh == mesh ? state.textures->size : 0;
        Job* raw = job.get();
        job->settings.progress = [raw](double fraction) { raw->progress = fraction; };
        if (settings.size == 0) job->tolerance = document.project().bodies[body].tolerance;
        job->thread = std::thread([raw] {
            lowerThisThreadsPriority();
            if (raw->tolerance) {
                Result<LevelChoice> choice =
                    chooseLevelForTolerance(*raw->mesh, *raw->tolerance, raw->settings);
                if (choice) {
                    raw->result = SurfaceTextures(*choice->textures);
                    choice->textures.reset();
                    raw->choice = std::move(*choice);
                } else {
                    raw->result = choice.error();
                }
            } else {
                raw->result = bakeSurfaceTextures(*raw->mesh, raw->settings, nullptr,
                                                  [raw] { return raw->cancel.load(); });
            }
            raw->done = true;
        });
        state.worker = job->thread.get_id();
        state.job = std::move(job);
    }
    // Meanwhile what the body had, where it is the same mesh (another size).
    return state.mesh == mesh ? state.textures : nullptr;
}

bool PhysicsBakes::poll(Document& document) {
    reapAbandoned();
    bool arrived = false;
    for (auto& [body, state] : bodies_) {
        if (!state.job || !state.job->done) continue;
        std::shared_ptr<Job> job = std::move(state.job);
        job->thread.join();  // finished: returns at once
        Result<SurfaceTextures>& result = *job->result;
        if (!result) {
            state.failedSettings = job->settings;
            state.failedMesh = job->mesh.get();
            state.error = result.error().message;
            arrived = true;
            continue;
        }
        auto textures = std::make_shared<const SurfaceTextures>(std::move(result).value());
        // A tolerance's pick: the size it picked is the size these textures were baked at.
        if (job->choice) {
            if (body >= document.bodyCount() ||
                !document.adoptLevelChoice(body, job->mesh.get(), job->settings, *job->choice))
                continue;
            job->settings.size = job->choice->size;
        }
        if (body < document.bodyCount() &&
            document.adoptPhysics(body, job->mesh.get(), job->settings, textures)) {
            state.mesh = job->mesh;
            state.settings = job->settings;
            state.textures = std::move(textures);
            arrived = true;
        }
    }
    return arrived;
}

bool PhysicsBakes::busy() const {
    for (const auto& [body, state] : bodies_) {
        if (state.job) return true;
    }
    return false;
}

bool PhysicsBakes::finishedWaiting() const {
    for (const auto& [body, state] : bodies_) {
        if (state.job && state.job->done) return true;
    }
    return false;
}

bool PhysicsBakes::resizing() const {
    for (const auto& [body, state] : bodies_) {
        if (state.job && state.job->previousSize > 0) return true;
    }
    return false;
}

std::optional<PhysicsBakes::Progress> PhysicsBakes::progress(std::size_t body) const {
    const auto it = bodies_.find(body);
    if (it == bodies_.end() || !it->second.job) return std::nullopt;
    const Job& job = *it->second.job;
    return Progress{job.settings.size, job.previousSize, job.progress.load()};
}

int PhysicsBakes::cancel(std::size_t body) {
    const auto it = bodies_.find(body);
    if (it == bodies_.end() || !it->second.job) return 0;
    const int previous = it->second.job->previousSize;
    abandon(it->second);
    return previous;
}

std::string PhysicsBakes::error(std::size_t body) const {
    const auto it = bodies_.find(body);
    return it == bodies_.end() ? std::string() : it->second.error;
}

std::thread::id PhysicsBakes::lastWorker(std::size_t body) const {
    const auto it = bodies_.find(body);
    return it == bodies_.end() ? std::thread::id() : it->second.worker;
}

void PhysicsBakes::abandon(BodyState& state) {
    state.job->cancel = true;
    abandoned_.push_back(std::move(state.job));
}

void PhysicsBakes::reapAbandoned() {
    // A finished job's destructor joins a thread that has already ended.
    std::erase_if(abandoned_, [](const std::shared_ptr<Job>& job) { return job->done.load(); });
}

}  // namespace plimsoll::editor
