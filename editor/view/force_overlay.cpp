// Force arrows, waterline and wet texels of the live preview (force_overlay.h).
#include "view/force_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace plimsoll::editor {

std::vector<OverlaySegment> waterlineOf(const TriangleMesh& mesh, const Pose& pose,
                                        const WaterModel& water, double time) {
    std::vector<Eigen::Vector3d> world(mesh.positions.size());
    std::vector<double> above(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        world[v] = pose.apply(mesh.positions[v]);
        above[v] = world[v].y() - water.height(world[v].x(), world[v].z(), time);
    }
    std::vector<OverlaySegment> segments;
    for (const auto& t : mesh.triangles) {
        std::array<Eigen::Vector3d, 2> crossing;
        int found = 0;
        for (int e = 0; e < 3 && found < 2; ++e) {
            const auto i = static_cast<std::size_t>(t[e]),
                       j = static_cast<std::size_t>(t[(e + 1) % 3]);
            // A sign change along the edge (a vertex exactly on the surface counts as above).
            if ((above[i] < 0) == (above[j] < 0)) continue;
            const double s = above[i] / (above[i] - above[j]);
            crossing[found++] = world[i] + s * (world[j] - world[i]);
        }
        if (found == 2) segments.push_back({crossing[0], crossing[1]});
    }
    return segments;
}

ForceOverlay buildForceOverlay(const World& world, const std::vector<const TriangleMesh*>& meshes) {
    ForceOverlay overlay;
    const Scene& scene = world.scene();
    const bool flat = scene.water.kind == WaterModel::Kind::Flat;
    for (std::size_t i = 0; i < world.bodies().size(); ++i) {
        const SimulatedBody& body = world.bodies()[i];
        const Eigen::Vector3d weight = body.mass.mass * scene.simulation.gravity;
        const double scale = weight.norm() > 0 ? 0.5 * body.boundingRadius / weight.norm() : 0.0;
        auto add = [&](const Eigen::Vector3d& at, const Eigen::Vector3d& force,
                       const Eigen::Vector3f& colour) {
            if (force.norm() <= 1e-6 * weight.norm()) return;
            overlay.arrows.push_back({at, at + scale * force, colour});
        };
        add(body.state.position, weight, kWeightColour);
        // The force World applies: Archimedes' on flat water, the pressure integral on waves.
        add(body.buoyancy.centerOfBuoyancy,
            flat ? body.buoyancy.force : body.buoyancy.pressureForce, kBuoyancyColour);
        add(body.buoyancy.centerOfBuoyancy, body.buoyancy.dragForce, kDragColour);
        if (i < meshes.size() && meshes[i]) {
            std::vector<OverlaySegment> line =
                waterlineOf(*meshes[i], body.pose(), scene.water, world.time());
            overlay.waterline.insert(overlay.waterline.end(), line.begin(), line.end());
        }
    }
    return overlay;
}

std::uint64_t texturesKey(int size, const std::vector<std::uint32_t>& texelIndex) {
    // FNV-1a over the size and the covered texels' places (about 1 ms at 1024^2).
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](std::uint64_t v) {
        h ^= v;
        h *= 1099511628211ull;
    };
    mix(static_cast<std::uint64_t>(size));
    mix(texelIndex.size());
    for (std::uint32_t index : texelIndex) mix(index);
    return h;
}

std::uint64_t texturesKey(const SurfaceTextures& t) { return texturesKey(t.size, t.texelIndex); }

WetTexelSamples wetTexelSamples(const SurfaceTextures& t) {
    return wetTexelSamples(t.size, t.texelIndex);
}

WetTexelSamples wetTexelSamples(int size, const std::vector<std::uint32_t>& texelIndex) {
    WetTexelSamples samples;
    samples.shown = std::min(size, kWetOverlayMaxSize);
    samples.key = texturesKey(size, texelIndex);
    const auto shown = static_cast<std::size_t>(samples.shown);
    std::vector<bool> taken(shown * shown, false);
    for (std::size_t i = 0; i < texelIndex.size(); ++i) {
        // The physics texel's place in the shown image (the same one when it is not smaller).
        const std::uint32_t index = texelIndex[i];
        const std::size_t x = static_cast<std::size_t>(index % size) * shown / size;
        const std::size_t y = static_cast<std::size_t>(index / size) * shown / size;
        const std::size_t texel = y * shown + x;
        if (taken[texel]) continue;
        taken[texel] = true;
        samples.entries.push_back(static_cast<std::uint32_t>(i));
        samples.texels.push_back(static_cast<std::uint32_t>(texel));
    }
    return samples;
}

OverlayImage wetTexelOverlay(const SimulatedBody& body, const WaterModel& water, double time) {
    return wetTexelOverlay(body, water, time, wetTexelSamples(body.textures));
}

OverlayImage wetTexelOverlay(const SimulatedBody& body, const WaterModel& water, double time,
                             const WetTexelSamples& samples) {
    const SurfaceTextures& t = body.textures;
    OverlayImage image;
    image.width = image.height = samples.shown;
    image.placement = t.placement;
    const auto texels = static_cast<std::size_t>(samples.shown) * samples.shown;
    image.rgba.resize(texels * 4);
    std::array<std::uint8_t, 4> dry{}, wet{};
    for (int k = 0; k < 3; ++k) {
        dry[k] = static_cast<std::uint8_t>(std::lround(255.0f * kDryColour[k]));
        wet[k] = static_cast<std::uint8_t>(std::lround(255.0f * kWetColour[k]));
    }
    dry[3] = wet[3] = 255;
    for (std::size_t texel = 0; texel < texels; ++texel)
        std::copy(dry.begin(), dry.end(), &image.rgba[4 * texel]);
    // The water's heights in one batch (vectorised for Gerstner waves, as the fast path asks
    // for them): one point at a time, the waves took most of a 256^2 image's time each frame.
    // The points' arrays are kept between calls (one a preview frame): sized once, not
    // allocated each frame.
    thread_local struct { std::vector<double> x, y, z, height; } points;
    const Pose pose = body.pose();
    const std::size_t n = samples.entries.size();
    for (std::vector<double>* column : {&points.x, &points.y, &points.z, &points.height})
        column->resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Eigen::Vector3d p = pose.apply(t.position[samples.entries[k]]);
        points.x[k] = p.x();
        points.y[k] = p.y();
        points.z[k] = p.z();
    }
    water.heights(n, points.x.data(), points.z.data(), time, points.height.data());
    for (std::size_t k = 0; k < n; ++k) {
        if (points.y[k] < points.height[k])
            std::copy(wet.begin(), wet.end(), &image.rgba[4 * std::size_t{samples.texels[k]}]);
    }
    return image;
}

}  // namespace plimsoll::editor
