// What the live preview draws over the 3D view, as world-space geometry (no GL: the window
// projects it with the camera, tests check it by hand): per body the weight at the centre of
// mass (red), buoyancy at the centre of buoyancy (green), drag there (blue), the waterline on
// the hull (where the mesh crosses the water surface), and the wet texels darker.
#pragma once

#include "document/overlay.h"

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/scene/world.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace plimsoll::editor {

inline const Eigen::Vector3f kWeightColour{1.0f, 0.12f, 0.12f};
inline const Eigen::Vector3f kBuoyancyColour{0.12f, 1.0f, 0.12f};
inline const Eigen::Vector3f kDragColour{0.25f, 0.45f, 1.0f};
inline const Eigen::Vector3f kWaterlineColour{0.95f, 0.95f, 0.30f};

struct OverlayArrow {
    Eigen::Vector3d from = Eigen::Vector3d::Zero();  ///< point of application, world, m
    Eigen::Vector3d to = Eigen::Vector3d::Zero();    ///< tip, world, m
    Eigen::Vector3f colour{1, 1, 1};
};

struct OverlaySegment {
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  ///< world, m
};

struct ForceOverlay {
    std::vector<OverlayArrow> arrows;
    std::vector<OverlaySegment> waterline;
};

/// The arrows of every body of `world` (lengths: the body's weight is half its bounding radius,
/// the other forces in proportion; forces under 1e-6 of the weight are left out), and the
/// waterline of each body whose mesh is given (meshes[i], object space; null: none).
ForceOverlay buildForceOverlay(const World& world, const std::vector<const TriangleMesh*>& meshes);

/// The segments where `mesh` at `pose` crosses the surface of `water` at `time`: per
/// triangle, the straight line between its edges' crossings of the height field.
std::vector<OverlaySegment> waterlineOf(const TriangleMesh& mesh, const Pose& pose,
                                        const WaterModel& water, double time);

/// Most texels a side of a wet-texel image: a larger physics texture is shown at this size,
/// one water test per shown texel, so that a frame's cost does not grow with the physics
/// texture (1024^2 took most of a frame on llvmpipe).
inline constexpr int kWetOverlayMaxSize = 256;

/// Which physics texels wetTexelOverlay tests: for each shown texel that any covered texel
/// falls in, the first such entry. Found once per set of textures (a walk over every covered
/// texel, 15 ms at 1024^2 on the test machine), then each frame tests at most
/// kWetOverlayMaxSize^2 entries.
struct WetTexelSamples {
    int shown = 0;                       ///< the image's texels a side
    std::vector<std::uint32_t> entries;  ///< covered-texel index into the textures
    std::vector<std::uint32_t> texels;   ///< its texel in the shown image (y * shown + x)
    std::uint64_t key = 0;               ///< texturesKey of the textures they were found for
};
WetTexelSamples wetTexelSamples(const SurfaceTextures& textures);
/// The same from the textures' size and covered texels' places alone (a worker's copy).
WetTexelSamples wetTexelSamples(int size, const std::vector<std::uint32_t>& texelIndex);
/// A fingerprint of the textures' layout (size and covered texels' places): samples found for
/// one set of textures serve another with the same key.
std::uint64_t texturesKey(const SurfaceTextures& textures);
std::uint64_t texturesKey(int size, const std::vector<std::uint32_t>& texelIndex);

/// The body's texels under the water darker than the dry ones: an overlay image over its
/// physics texture, at its size or kWetOverlayMaxSize, whichever is smaller (texels nothing
/// maps to keep the dry colour; a shown texel takes the first entry that falls in it).
OverlayImage wetTexelOverlay(const SimulatedBody& body, const WaterModel& water, double time);
/// The same with the samples found before (wetTexelSamples of the body's textures).
OverlayImage wetTexelOverlay(const SimulatedBody& body, const WaterModel& water, double time,
                             const WetTexelSamples& samples);

/// The dry and wet colours of wetTexelOverlay (the body colour, and it darkened and blued).
inline const Eigen::Vector3f kDryColour{0.80f, 0.78f, 0.72f};
inline const Eigen::Vector3f kWetColour{0.30f, 0.34f, 0.42f};

}  // namespace plimsoll::editor
