// Texture against exact submerged volume (volume_check.h).
#include "plimsoll/physics/volume_check.h"

namespace plimsoll {

Result<SubmergedVolumeCheck> checkSubmergedVolume(BuoyancyBackend& backend, std::size_t bodyId,
                                                  const TriangleMesh& mesh, const BodyFrame& frame,
                                                  double waterLevel, const FluidSettings& fluid) {
    const BodyRequest request{bodyId, frame, fluid};
    BuoyancyResult texture;
    if (Status s = backend.evaluate({&request, 1}, WaterModel::flat(waterLevel), {&texture, 1});
        !s.ok())
        return s.error();
    // The volume does not depend on the centre of mass the torques are taken about, so the
    // exact clip may use the frame as it is.
    const BuoyancyResult exact = evaluateBuoyancyExact(mesh, frame, waterLevel, fluid);
    SubmergedVolumeCheck check;
    check.texture = texture.submergedVolume;
    check.exact = exact.submergedVolume;
    check.error = check.texture - check.exact;
    check.relativeError = check.exact != 0 ? check.error / check.exact : 0.0;
    return check;
}

}  // namespace plimsoll
