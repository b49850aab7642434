// The bodies' physics solids as a project run builds them (scene_loader.h, PreparedBodyMesh:
// the repaired solid, its openings and their caps), worked out on workers for the panels: the
// repair of an open hull takes seconds, never a frame. A body's solid is worked out again when
// its mesh or its caps' heights change (a cap's open or sealed mode does not change the solid).
// No GL and no ImGui here.
#pragma once

#include "document/document.h"

#include "plimsoll/project/scene_loader.h"

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

class PhysicsSolids {
public:
    struct Solid {
        /// The last solid worked out for the body (null: none yet); it may be of settings the
        /// body no longer has while `working`.
        std::shared_ptr<const PreparedBodyMesh> prepared;
        /// The solid and its caps alone (null without openings), for the view: they share
        /// `prepared`'s lifetime.
        std::shared_ptr<const TriangleMesh> solid, caps;
        std::string error;     ///< why the last one failed ("" when it did not)
        bool working = false;  ///< a newer one is being worked out
    };
    /// The body's solid for this frame; starts working it out on a worker when the body's
    /// mesh or cap heights changed. Never works on the calling thread.
    Solid solidFor(const Document& document, std::size_t body);
    /// Takes in finished solids; true when one arrived (the views then refresh).
    bool poll();
    /// Waits for every solid under way and takes it in (scripts and tests).
    void wait();

private:
    struct Job;
    struct Key {
        const TriangleMesh* mesh = nullptr;
        bool closeOpenings = true;
        std::vector<std::optional<double>> heights;
        bool operator==(const Key&) const = default;
    };
    struct BodyState {
        std::optional<Key> key;  ///< what `solid` (or the job under way) was made from
        Solid solid;
        std::shared_ptr<Job> job;
    };
    std::map<std::size_t, BodyState> bodies_;
};

}  // namespace plimsoll::editor
