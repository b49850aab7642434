#include "plimsoll/scene/scene_hydrostatics.h"

#include "plimsoll/graph/graph.h"
#include "plimsoll/surface/painted_map.h"

namespace plimsoll {

Result<FloatingBody> floatingBodyOf(const SceneBody& body, const MediumDesc& medium) {
    if (!body.mass || !body.textures || !body.parts.mesh) {
        return makeError(ErrorKind::invalidArgument, body.label + ": not baked");
    }
    FloatingBody out;
    out.body = {body.mass->mass, body.mass->centerOfMass, {}, {}};
    if (!body.desc.waterGraph || !body.parts.waterGraph) return out;
    GraphSettings settings = body.desc.waterGraph->settings;
    settings.density = medium.density;  // the graph holds the medium's water, as World's does
    // The permeability as World samples it (World::makeFlooding): the graph's permeable
    // samples are where water gets in, the body's openings.
    std::vector<double> permeability;
    if (body.parts.permeabilityMap) {
        permeability = sampleAtTexels(*body.parts.permeabilityMap, *body.textures,
                                      body.desc.waterGraph->permeability);
    }
    Result<WaterGraphSimulation> graph = WaterGraphSimulation::create(
        *body.parts.waterGraph, *body.textures, permeability, settings);
    if (!graph) return withContext(body.label + ": water graph: ", graph.error());
    const MassProperties full = graph->compose(*body.mass, Eigen::Matrix3d::Identity());
    out.body.mass = full.mass;
    out.body.centerOfMass = full.centerOfMass;
    out.body.freeSurfaces = graphFreeSurfaces(*body.parts.waterGraph, settings.density);
    out.graphWater = graph->storedWater();
    for (const ExchangeSample& sample : graph->samples())
        out.body.openings.push_back(sample.position);
    return out;
}

Result<HydrostaticsSettings> hydrostaticsSettingsOf(const MediumDesc& medium,
                                                    const Eigen::Vector3d& gravity) {
    HydrostaticsSettings settings;
    settings.density = medium.density;
    settings.gravity = gravity.norm();
    if (!(settings.gravity > 0)) {
        return makeError(ErrorKind::invalidArgument, "without gravity nothing floats");
    }
    return settings;
}

}  // namespace plimsoll
