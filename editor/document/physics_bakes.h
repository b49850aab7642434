// The document's physics textures baked off the UI thread: a panel that needs a body's
// textures asks for them every frame and gets the ones baked at the body's current size, or,
// while that size bakes on a worker (below the UI's priority, with progress and Cancel), the
// ones the body had before (another size) so that what is on screen keeps working. A finished
// bake goes into the document when the frame loop polls; one made stale by a later edit (a new
// size, a new mesh) is dropped. Document::physicsTextures stays the synchronous way for the
// command line and scripts. No GL and no ImGui here.
#pragma once

#include "document/document.h"

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace plimsoll::editor {

/// Below the calling thread's priority (Linux: nice 10, which the threads it starts inherit),
/// so that a bake on every core still leaves the UI thread its frame.
void lowerThisThreadsPriority();

class PhysicsBakes {
public:
    PhysicsBakes() = default;
    PhysicsBakes(const PhysicsBakes&) = delete;
    PhysicsBakes& operator=(const PhysicsBakes&) = delete;
    /// Cancels the bakes still running and waits for them to stop.
    ~PhysicsBakes();

    /// The body's textures for this frame: the document's when baked at the body's size;
    /// otherwise their bake starts (or goes on) on a worker, and meanwhile the textures the
    /// body last had here, at another size, or null. Never bakes on the calling thread.
    std::shared_ptr<const SurfaceTextures> texturesFor(Document& document, std::size_t body);
    /// Puts finished bakes that still fit into the document; true when one arrived (the views
    /// then refresh what they draw from the textures).
    bool poll(Document& document);
    /// Whether a bake runs or waits for poll().
    bool busy() const;
    /// Whether a finished bake waits for poll() (an idle frame loop then draws a frame).
    bool finishedWaiting() const;
    /// Whether a bake of a new size runs (textures of another size are shown meanwhile): a
    /// user's change whose progress an idle window keeps showing.
    bool resizing() const;

    struct Progress {
        int size = 0;          ///< the size being baked
        int previousSize = 0;  ///< the size of the textures shown meanwhile (0: none)
        double fraction = 0;   ///< 0..1
    };
    /// The body's bake under way, if any.
    std::optional<Progress> progress(std::size_t body) const;
    /// Stops the body's bake without waiting for it; the size to set back (that of the
    /// textures shown meanwhile; 0: none). Setting it makes texturesFor adopt them again.
    int cancel(std::size_t body);
    /// Why the body's last bake failed ("" when it did not); kept until its settings change.
    std::string error(std::size_t body) const;
    /// The thread the body's last started bake ran on (tests: not the caller's).
    std::thread::id lastWorker(std::size_t body) const;

private:
    struct Job;
    struct BodyState {
        /// The last textures this body had and what they were baked from.
        std::shared_ptr<const TriangleMesh> mesh;
        BakeSettings settings;
        std::shared_ptr<const SurfaceTextures> textures;
        std::shared_ptr<Job> job;  ///< the bake under way (or done, not yet polled)
        /// A failed bake's settings and message: not retried every frame.
        std::optional<BakeSettings> failedSettings;
        const TriangleMesh* failedMesh = nullptr;
        std::string error;
        std::thread::id worker;
    };
    void abandon(BodyState& state);
    void reapAbandoned();

    std::map<std::size_t, BodyState> bodies_;
    /// Cancelled bakes winding down: dropped once finished, never waited for by the UI.
    std::vector<std::shared_ptr<Job>> abandoned_;
};

}  // namespace plimsoll::editor
