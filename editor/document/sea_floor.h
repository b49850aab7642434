// The live preview's sea floor setting (preview.h applies it; settings.h keeps it).
#pragma once

namespace plimsoll::editor {

/// The preview's sea floor: a horizontal plane `depth` metres below the water's mean level that
/// the bodies rest on. An aid of the editor's preview (a sinking body stays in view), applied
/// as World's external force beside the grab spring; neither the scene nor the engine has it.
struct SeaFloor {
    static constexpr double kDefaultDepth = 5.0;  ///< m
    bool enabled = false;
    double depth = kDefaultDepth;  ///< m below WaterModel::level, > 0
    double friction = 0.5;         ///< Coulomb's coefficient along the floor
    bool operator==(const SeaFloor&) const = default;
};

}  // namespace plimsoll::editor
