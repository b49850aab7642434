#include "plimsoll/graph/graph.h"

#include "plimsoll/geometry/box.h"
#include "plimsoll/physics/buoyancy.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <set>

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

// The box's volume below a level in closed form (plimsoll_eval BoxSpans, what the level search
// asks) against the box clipped (RotatedBox::below, held above to the exact mesh clip), over
// rotations drawn at random, near upright (one or two edges' spans along the vertical tiny:
// where the closed form's pieces would lose digits if they divided by them) and exactly upright
// or on a side, boxes of unequal edges, and levels from below the box to above it. Both are
// rounding apart: at most 1e-14 of the box's volume.
TEST(GraphBoxClip, ClosedFormVolumeEqualsTheClip) {
    std::mt19937_64 rng(23);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worst = 0;
    int cases = 0;
    for (int k = 0; k < 600; ++k) {
        const plimsoll_eval::Vec3 size{0.3 + 2 * unit(rng), 0.3 + 2 * unit(rng),
                                       0.3 + 2 * unit(rng)};
        Eigen::Matrix3d R;
        if (k % 4 == 0) {
            R = (Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)))
                    .normalized()
                    .toRotationMatrix();
        } else if (k % 4 == 3 && k < 40) {  // exactly upright, on its side, on its end
            const double quarter = 1.5707963267948966;
            R = k % 3 == 0 ? Eigen::Matrix3d::Identity()
                : k % 3 == 1
                    ? Eigen::AngleAxisd(quarter, Eigen::Vector3d::UnitX()).toRotationMatrix()
                    : Eigen::AngleAxisd(quarter, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        } else {  // heeled and trimmed by angles from 1e-12 to 0.3 rad, one of them perhaps zero
            const double roll = std::pow(10.0, -12 + 11.5 * unit(rng)) * (k % 2 ? 1 : -1);
            const double pitch = k % 4 == 2 ? 0.0 : std::pow(10.0, -12 + 11.5 * unit(rng));
            R = (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) *
                 Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()))
                    .toRotationMatrix();
        }
        plimsoll_eval::Mat3 m;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m.m[i][j] = R(i, j);
        const plimsoll_eval::RotatedBox clipped(size, m);
        const plimsoll_eval::BoxSpans spans(size, m);
        const double volume = size.x * size.y * size.z;
        for (int l = 0; l <= 40; ++l) {
            const double level = (-0.6 + 1.2 * l / 40.0 + 0.01 * normal(rng)) * spans.span;
            const double reference = std::max(0.0, clipped.below<false>(level).volume);
            const double got = spans.below(level);
            const double e = std::abs(got - reference) / volume;
            EXPECT_LE(e, 1e-14) << k << " level " << level;
            worst = std::max(worst, e);
            ++cases;
        }
    }
    std::printf("  closed-form box volume against the clip: %d cases, worst %.2e of the box\n",
                cases, worst);
}

// The level search (GraphFlow::levelOffset: Brent's bracketRoot on the node's volume) against
// the bisection it replaced (levelOffsetBisection, kept as the reference): box and sphere
// nodes, random rotations, fills from empty to full. Both stop on a bracket of at most
// 1e-12 (1 + |h|) m about the float volume's root and return its midpoint, so they agree
// within that (the stated bound), and the water the level holds is the node's own to
// 1e-12 of the capacity. The volume-only clip gives the full clip's volume bit for bit.
TEST(GraphLevel, BracketRootAgreesWithTheBisectionReference) {
    using plimsoll_eval::GraphFlow;
    using plimsoll_eval::GraphNodeState;
    std::vector<GraphNodeState> nodes;
    nodes.push_back({{0.0, 0.0, -2.25}, 2.72, 0.0, false, {2.0, 1.0, 1.5}});
    nodes.push_back({{0.0, 0.0, 2.25}, 1.45, 0.0, false, {1.07, 1.0, 1.5}});
    nodes.push_back({{0.5, 0.2, 0.0}, 0.8, 0.0, false, {}});  // a sphere
    GraphFlow flow;
    flow.reset(nodes, {}, 1);
    std::mt19937_64 rng(37);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> fill(0.0, 1.0);
    double worst = 0;
    for (int k = 0; k < 600; ++k) {
        Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
        if (k % 3 == 0)
            q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * normal(rng), Eigen::Vector3d::UnitX()));
        if (k % 7 == 0) q = Eigen::Quaterniond::Identity();
        q.normalize();
        const Eigen::Matrix3d R = q.toRotationMatrix();
        plimsoll_eval::Mat3 m;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m.m[i][j] = R(i, j);
        for (std::size_t node = 0; node < nodes.size(); ++node) {
            const double capacity = nodes[node].capacity;
            const double water = k % 11 == 0 ? capacity * 1e-9 : capacity * fill(rng);
            const double fast = flow.levelOffset(node, water, m);
            const double reference = flow.levelOffsetBisection(node, water, m);
            const double bound = 1e-12 * (1.0 + std::abs(reference));
            EXPECT_LE(std::abs(fast - reference), bound) << k << " node " << node;
            worst = std::max(worst, std::abs(fast - reference) / bound);
            EXPECT_NEAR(flow.volumeAtLevel(node, fast, m), water, 1e-11 * capacity) << k;
            if (nodes[node].isBox()) {
                const plimsoll_eval::RotatedBox box(flow.nodes()[node].box, m);
                const double h = 0.8 * (fill(rng) - 0.5);
                const plimsoll_eval::ClippedVolume full = box.below(h);
                EXPECT_EQ(box.below<false>(h).volume, full.volume) << k;
            }
        }
    }
    std::printf("levelOffset against the bisection: worst %.2f of the 1e-12 (1 + |h|) bound\n",
                worst);
}

// The exchange's outside surface on the lattice (plimsoll_eval exchangeSurfaces) against its
// definition worked out here point by point (the four nodes about the point, asked one at a
// time, interpolated), and against the water itself: a sine's interpolant misses it by at most
// s^2 / 8 (|f_xx| + |f_zz|) and by a fair part of that. Each node is asked once; clusters far
// apart (the bounding box too large to index) give the same surface; equal heights give that
// height exactly.
TEST(GraphExchangeLattice, InterpolatesTheNodesAboutEachPointAskingEachOnce) {
    using plimsoll_eval::Vec3;
    const double s = plimsoll_eval::kExchangeLatticeSpacing;
    const double a = 0.2, kx = 0.9, kz = -0.6;
    auto water = [&](double x, double z) { return 0.1 + a * std::sin(kx * x + kz * z + 0.4); };
    const double bound = s * s / 8.0 * a * (kx * kx + kz * kz);
    std::mt19937_64 rng(5);
    std::normal_distribution<double> normal;
    for (const bool apart : {false, true}) {
        // Two openings' worth of points, 0.3 m across, stacked up a hull side; `apart`: the
        // second 5 km away.
        std::vector<Vec3> world;
        for (int k = 0; k < 900; ++k) {
            const bool second = k % 3 == 0;
            const double cx = second ? (apart ? 5000.0 : -1.7) : 0.4, cz = second ? 2.2 : -0.9;
            world.push_back({cx + 0.3 * normal(rng), -0.2 * (k % 5), cz + 0.3 * normal(rng)});
        }
        std::vector<double> asked, surface;
        std::set<std::pair<double, double>> seen;
        plimsoll_eval::ExchangeLattice lattice;
        int calls = 0;
        plimsoll_eval::exchangeSurfaces(
            world, s,
            [&](std::size_t n, const double* x, const double* z, double* out) {
                ++calls;
                for (std::size_t i = 0; i < n; ++i) {
                    EXPECT_TRUE(seen.insert({x[i], z[i]}).second) << "asked twice";
                    out[i] = water(x[i], z[i]);
                }
            },
            lattice, surface);
        EXPECT_EQ(calls, 1);
        ASSERT_EQ(surface.size(), world.size());
        std::set<std::pair<double, double>> needed;
        double worst = 0;
        for (std::size_t p = 0; p < world.size(); ++p) {
            const double gx = world[p].x / s, gz = world[p].z / s;
            const double i = std::floor(gx), j = std::floor(gz);
            const double x0 = i * s, x1 = (i + 1) * s, z0 = j * s, z1 = (j + 1) * s;
            for (const auto& node : {std::pair{x0, z0}, {x1, z0}, {x0, z1}, {x1, z1}})
                needed.insert(node);
            const double tx = gx - i, tz = gz - j;
            const double expected = (1 - tz) * ((1 - tx) * water(x0, z0) + tx * water(x1, z0)) +
                                    tz * ((1 - tx) * water(x0, z1) + tx * water(x1, z1));
            EXPECT_NEAR(surface[p], expected, 1e-14) << p;
            const double miss = std::abs(surface[p] - water(world[p].x, world[p].z));
            EXPECT_LE(miss, bound) << p;
            worst = std::max(worst, miss);
        }
        EXPECT_EQ(seen, needed);  // every node needed, none more
        EXPECT_GT(worst, 0.2 * bound);
        EXPECT_LT(needed.size(), world.size() / 4);
        std::printf("  lattice %s: %zu points, %zu heights asked; worst miss %.2e m (bound %.2e)\n",
                    apart ? "5 km apart" : "one body", world.size(), needed.size(), worst, bound);

        // Flat: the same height everywhere comes back exactly.
        plimsoll_eval::exchangeSurfaces(
            world, s,
            [](std::size_t n, const double*, const double*, double* out) {
                std::fill(out, out + n, -0.123456789);
            },
            lattice, surface);
        for (const double f : surface) EXPECT_EQ(f, -0.123456789);
    }
}

}  // namespace
}  // namespace test_graph_clip
}  // namespace plimsoll
