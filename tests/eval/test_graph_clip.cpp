#include "plimsoll/graph/graph.h"

#include "plimsoll/geometry/box.h"
#include "plimsoll/physics/buoyancy.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace plimsoll {
namespace test_graph_clip {
namespace {

// The evaluation core's box-compartment clip (plimsoll_eval/graph.hpp, the one the engine and
// the runtime step with) against two independent references: the exact mesh clip of the same
// box (evaluateBuoyancyExact over makeBox) at random rotations and levels, and the analytic
// slab of an upright box.
TEST(GraphBoxClip, EqualsTheExactMeshClipAndTheUprightSlab) {
    const Eigen::Vector3d size(2.0, 1.0, 1.5);
    const TriangleMesh box = makeBox(size);
    std::mt19937_64 rng(16);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> uniform(-1.2, 1.2);
    int wet = 0;
    for (int k = 0; k < 300; ++k) {
        Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
        q.normalize();
        const Eigen::Matrix3d R = q.toRotationMatrix();
        const double level = uniform(rng);
        BodyFrame frame;
        frame.pose.rotation = R;
        const BuoyancyResult exact = evaluateBuoyancyExact(box, frame, level, FluidSettings{});
        plimsoll_eval::Mat3 m;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m.m[i][j] = R(i, j);
        const plimsoll_eval::ClippedVolume clip =
            plimsoll_eval::clipBoxBelow({size.x(), size.y(), size.z()}, m, level);
        const double volume = clip.volume > 0 ? clip.volume : 0.0;
        EXPECT_NEAR(volume, exact.submergedVolume, 1e-14 * size.prod()) << k;
        if (exact.submergedVolume > 1e-9) {
            ++wet;
            const Eigen::Vector3d centroid =
                Eigen::Vector3d(clip.moment.x, clip.moment.y, clip.moment.z) / clip.volume;
            EXPECT_LE((centroid - exact.centerOfBuoyancy).norm(), 1e-12) << k;
        }
    }
    EXPECT_GT(wet, 100);
    // Upright: the slab below y = h of a 2 x 1 x 1.5 box is 2 x 1.5 x (h + 0.5), its centroid
    // halfway down the slab.
    for (double h : {-0.4, -0.1, 0.0, 0.25, 0.49}) {
        const plimsoll_eval::ClippedVolume clip =
            plimsoll_eval::clipBoxBelow({2.0, 1.0, 1.5}, plimsoll_eval::Mat3{}, h);
        EXPECT_NEAR(clip.volume, 3.0 * (h + 0.5), 1e-14) << h;
        EXPECT_NEAR(clip.moment.y / clip.volume, 0.5 * (h - 0.5), 1e-14) << h;
        EXPECT_NEAR(clip.moment.x, 0.0, 1e-14) << h;
        EXPECT_NEAR(clip.moment.z, 0.0, 1e-14) << h;
    }
}

}  // namespace
}  // namespace test_graph_clip
}  // namespace plimsoll
