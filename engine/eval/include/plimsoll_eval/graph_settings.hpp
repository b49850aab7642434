// The water graph's settings (docs/design.md, "Water graph"): how water comes in through the
// permeable surface, how it moves between nodes, and the water inside. One struct for the
// engine (plimsoll::GraphSettings, graph.h), the evaluation core's step (graph.hpp) and the
// runtime library (plimsoll_runtime::GraphSettings, read from a bundle's manifest): a new
// setting is one member here plus its readers and writers. Standard library only and C++17:
// the runtime installs this header beside its public runtime.hpp, which includes it.
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>

namespace plimsoll_eval {

/// How water comes in through a permeable texel (per texel i, permeability k_i in 0..1,
/// |A_i| its area, head h = outside depth - inside head, both >= 0; negative h flows out).
enum class InflowModel {
    /// The paper's constant factor: q_i = rate k_i |A_i| h (m^3/s; rate in 1/s).
    Linear,
    /// Hydrostatic head (Torricelli): q_i = C_d k_i |A_i| sqrt(2 g |h|), signed as h.
    Torricelli,
};

/// How water moves between nodes.
enum class FlowMode {
    /// Downhill along open pipes: findDischargeNode (paper Algorithm 1) and Poiseuille's law
    /// Q = pi dp r^4 / (8 mu L), dp = rho g dh (paper eq. 14).
    Poiseuille,
    /// Absorbent materials (paper figure 16): along every open pipe from the fuller node
    /// (water / capacity) to the emptier, Q = pi dp r^4 / (8 mu L) with
    /// dp = diffusionPressure * (fill difference), whatever the heights.
    Diffusion,
};

/// The names project files and bundle manifests give the models ("inflow", "flow").
inline const char* inflowModelName(InflowModel model) {
    return model == InflowModel::Torricelli ? "torricelli" : "linear";
}
inline const char* flowModelName(FlowMode mode) {
    return mode == FlowMode::Diffusion ? "diffusion" : "poiseuille";
}

namespace graph_settings_detail {

/// The one of `values` that `nameOf` calls `name`, into `out`; false, `out` unchanged, for none.
template <typename Enum>
bool fromName(const std::string& name, std::initializer_list<Enum> values,
              const char* (*nameOf)(Enum), Enum& out) {
    for (const Enum value : values) {
        if (name == nameOf(value)) {
            out = value;
            return true;
        }
    }
    return false;
}

}  // namespace graph_settings_detail

/// The model named `name` (inflowModelName's); false, `out` unchanged, for an unknown name.
inline bool inflowModelFromName(const std::string& name, InflowModel& out) {
    return graph_settings_detail::fromName(name, {InflowModel::Linear, InflowModel::Torricelli},
                                           inflowModelName, out);
}
/// The mode named `name` (flowModelName's); false, `out` unchanged, for an unknown name.
inline bool flowModeFromName(const std::string& name, FlowMode& out) {
    return graph_settings_detail::fromName(name, {FlowMode::Poiseuille, FlowMode::Diffusion},
                                           flowModelName, out);
}

/// The graph simulation's settings: the models (a project's or a manifest's `water_graph`:
/// inflow, flow, seed, ...) and the medium inside (density, viscosity, gravity: the scene's,
/// or in the runtime the caller's world, as for its Fluid).
struct GraphSettings {
    InflowModel inflow = InflowModel::Linear;
    double inflowRate = 1.0;            ///< Linear: 1/s, >= 0
    double dischargeCoefficient = 0.6;  ///< Torricelli: C_d, 0..1
    FlowMode flow = FlowMode::Poiseuille;
    double diffusionPressure = 1000.0;  ///< Diffusion: Pa at a full fill difference, >= 0
    /// Water in a partly filled node sits at its lowest side along gravity (a sphere cap, or
    /// the part of the box below a level plane), so its centre of mass moves as the body
    /// heels. Off: the water sits at the node's position (paper eq. 16).
    bool freeSurface = false;
    std::uint64_t seed = 1;     ///< neighbour order of findDischargeNode
    double density = 1000.0;    ///< of the water, kg/m^3
    double viscosity = 1.0e-3;  ///< of the water, Pa s (> 0 for Poiseuille)
    double gravity = 9.81;      ///< m/s^2, along -y (the engine's kStandardGravity)

    /// The exchange's factor: 1/s (linear) or C_d sqrt(2 g) in m^0.5/s (Torricelli).
    double exchangeFactor() const {
        return inflow == InflowModel::Torricelli ? dischargeCoefficient * std::sqrt(2.0 * gravity)
                                                 : inflowRate;
    }

    // Spelled out: the runtime compiles this header as C++17, which has no defaulted ==.
    bool operator==(const GraphSettings& o) const {
        return inflow == o.inflow && inflowRate == o.inflowRate &&
               dischargeCoefficient == o.dischargeCoefficient && flow == o.flow &&
               diffusionPressure == o.diffusionPressure && freeSurface == o.freeSurface &&
               seed == o.seed && density == o.density && viscosity == o.viscosity &&
               gravity == o.gravity;
    }
    bool operator!=(const GraphSettings& o) const { return !(*this == o); }
};

}  // namespace plimsoll_eval
