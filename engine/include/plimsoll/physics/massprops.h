// Mass properties: mass, centre of mass and inertia tensor of a body, two ways.
//  - exact, from the closed triangle mesh (Mirtich 1996; Eberly, "Polyhedral Mass
//    Properties (Revisited)", 2002): the reference everything else is held against;
//  - from the baked surface textures (paper section 3.1, corrected in docs/design.md,
//    "Mass properties"): the same integrals turned into sums over covered texels, which also
//    run per frame for deforming bodies.
// Material models combine by adding their MassProperties (operator+).
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>

#include <vector>

namespace plimsoll {

struct SurfaceTextures;

struct MassProperties {
    double mass = 0;                                         ///< kg
    double volume = 0;                                       ///< enclosed volume, m^3
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  ///< object space, m
    /// Inertia tensor about the centre of mass, object axes, kg m^2 (products of inertia
    /// carry the minus sign: I = integral of (r.r Id - r r^T) dm).
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

/// Sum of two bodies' mass properties (parallel-axis theorem). The volume is the larger of the
/// two: both describe the same enclosed space, not two disjoint ones.
MassProperties operator+(const MassProperties& a, const MassProperties& b);

/// `a` with the part `b` of it taken out (a solid with an empty space inside its surface: an
/// open hull's walls are its sealed body less the space behind its caps). The volume stays a's.
MassProperties operator-(const MassProperties& a, const MassProperties& b);

/// A solid of uniform `density` less the part `hollow` of its space that holds no material
/// (given at density 1: mass = volume): an open hull's walls from its sealed body. `solid`
/// unchanged when `hollow` has no mass.
MassProperties withoutHollow(const MassProperties& solid, const MassProperties& hollow,
                             double density);

/// Solid of uniform density (kg/m^3) bounded by a closed, outward-oriented triangle mesh.
MassProperties exactSolidMassProperties(const TriangleMesh& mesh, double density);

/// Thin shell of uniform surface density (kg/m^2) on the mesh's triangles (exact: each triangle
/// a uniform lamina). volume is still the enclosed volume.
MassProperties exactShellMassProperties(const TriangleMesh& mesh, double surfaceDensity);

/// Solid of uniform density from the textures: V = sum A_y y, first and second moments from
/// the divergence theorem with the fields of docs/design.md ("Mass properties"), evaluated
/// about the textures' centre so bodies far from the origin keep their digits.
MassProperties textureSolidMassProperties(const SurfaceTextures& textures, double density);

/// Thin shell from the textures: point masses sigma_i * area_i at p_i. surfaceDensity holds one
/// value per covered texel (kg/m^2, a painted map sampled at the texels) or is empty for the
/// uniform value `uniformSurfaceDensity`.
MassProperties textureShellMassProperties(const SurfaceTextures& textures,
                                          double uniformSurfaceDensity,
                                          const std::vector<double>& surfaceDensity = {});

}  // namespace plimsoll
