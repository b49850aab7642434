// The C++ reference of kernels/graph.cl (compute.h evaluateExchangeReference): the water-graph
// exchange through permeable texels (paper 4.2; graph.h for how the sums are used), in double
// precision over every sample.
#include "plimsoll/physics/buoyancy_backend.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plimsoll {

void evaluateExchangeReference(std::span<const ExchangeSample> samples, std::size_t nodes,
                               const ExchangeFrame& frame, const WaterModel& water,
                               ExchangeSums& sums) {
    sums.inflow.assign(nodes, 0.0);
    sums.outflow.assign(nodes, 0.0);
    sums.outsideTop.assign(nodes, -std::numeric_limits<double>::infinity());
    for (const ExchangeSample& s : samples) {
        const Eigen::Vector3d p = frame.pose.apply(s.position);
        const double f = water.height(p.x(), p.z(), frame.time);
        const double outside = std::max(0.0, f - p.y());
        const double inside = std::max(0.0, frame.nodeSurface[s.node] - p.y());
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

}  // namespace plimsoll
