// The C++ reference of kernels/graph.cl (compute.h evaluateExchangeReference): the water-graph
// exchange through permeable texels (paper 4.2; graph.h for how the sums are used), in double
// precision over every sample, the outside water taken on the exchange's lattice; and the
// same pass with the water's height at every sample, the reference the lattice is held to.
#include "plimsoll/physics/buoyancy_backend.h"

#include "plimsoll_eval/graph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plimsoll {

namespace {

/// The pass over the samples at world positions `world` under the outside surface surface[i].
void exchangeSums(std::span<const ExchangeSample> samples, std::size_t nodes,
                  const ExchangeFrame& frame, const std::vector<plimsoll_eval::Vec3>& world,
                  const std::vector<double>& surface, ExchangeSums& sums) {
    sums.inflow.assign(nodes, 0.0);
    sums.outflow.assign(nodes, 0.0);
    sums.outsideTop.assign(nodes, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const ExchangeSample& s = samples[i];
        const double y = world[i].y;
        const double f = surface[i];
        const double outside = std::max(0.0, f - y);
        const double inside = std::max(0.0, frame.nodeSurface[s.node] - y);
        const double head = outside - inside;
        if (head == 0) continue;
        const double q = frame.torricelli ? frame.factor * s.weight * std::sqrt(std::abs(head))
                                          : frame.factor * s.weight * std::abs(head);
        if (head > 0) {
            sums.inflow[s.node] += q;
            sums.outsideTop[s.node] = std::max(sums.outsideTop[s.node], f);
        } else {
            sums.outflow[s.node] += q;
        }
    }
}

void worldPositions(std::span<const ExchangeSample> samples, const Pose& pose,
                    std::vector<plimsoll_eval::Vec3>& world) {
    world.resize(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const Eigen::Vector3d p = pose.apply(samples[i].position);
        world[i] = {p.x(), p.y(), p.z()};
    }
}

}  // namespace

void evaluateExchangeReference(std::span<const ExchangeSample> samples, std::size_t nodes,
                               const ExchangeFrame& frame, const WaterModel& water,
                               ExchangeSums& sums) {
    // The outside surface as the runtime takes it: the water on the exchange's lattice,
    // interpolated (plimsoll_eval exchangeSurfaces). Per thread, reused.
    thread_local std::vector<plimsoll_eval::Vec3> world;
    thread_local std::vector<double> surface;
    thread_local plimsoll_eval::ExchangeLattice lattice;
    worldPositions(samples, frame.pose, world);
    if (water.kind == WaterModel::Kind::Flat) {
        surface.assign(samples.size(), water.height(0.0, 0.0, frame.time));
    } else {
        plimsoll_eval::exchangeSurfaces(
            world, plimsoll_eval::kExchangeLatticeSpacing,
            [&](std::size_t count, const double* x, const double* z, double* out) {
                for (std::size_t i = 0; i < count; ++i)
                    out[i] = water.height(x[i], z[i], frame.time);
            },
            lattice, surface);
    }
    exchangeSums(samples, nodes, frame, world, surface, sums);
}

void evaluateExchangePointwise(std::span<const ExchangeSample> samples, std::size_t nodes,
                               const ExchangeFrame& frame, const WaterModel& water,
                               ExchangeSums& sums) {
    std::vector<plimsoll_eval::Vec3> world;
    worldPositions(samples, frame.pose, world);
    std::vector<double> surface(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i)
        surface[i] = water.height(world[i].x, world[i].z, frame.time);
    exchangeSums(samples, nodes, frame, world, surface, sums);
}

}  // namespace plimsoll
