// Wave radiation at bake time: the frequency-dependent added mass A(omega) and radiation damping
// B(omega) of a floating body, 6 x 6, in deep water, from its wetted surface below the
// equilibrium waterline. A low-order panel method (constant-strength sources on flat triangles,
// collocation at the centroids, as in WAMIT's low-order method) with the deep-water
// free-surface Green function: Rankine part 1/r + 1/r' integrated exactly over each triangle,
// wave part from its integral representation (docs/radiation.md has the derivation). The
// infinite-frequency added mass uses 1/r - 1/r' (the free surface acts as phi = 0).
//
// The normal-velocity condition and the potential are averaged over each panel (three points)
// rather than taken at its centroid (on triangles the centroid rule converged like the panel
// size; docs/radiation.md has the figures).
//
// Axes are the engine's: y up, the calm free surface is the plane y = 0 of the frame the panels
// are given in. Modes 0..2 are translations along x, y (heave), z; 3..5 rotations about x, y, z
// through the reference point. Irregular frequencies of the source formulation (the sloshing
// modes of the body's interior, from K a ~ 2 for a hemisphere of radius a) are removed by a lid
// of sources on the interior waterplane (docs/radiation.md).
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <complex>
#include <vector>

namespace plimsoll {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Mode indices of the 6 x 6 matrices.
enum RadiationMode : int {
    kSurgeX = 0,
    kHeaveY = 1,
    kSwayZ = 2,
    kRollX = 3,
    kYawY = 4,
    kPitchZ = 5
};

/// One flat source panel of the wetted surface (a triangle below y = 0).
struct RadiationPanel {
    std::array<Eigen::Vector3d, 3> vertices;  ///< counter-clockwise seen from the water
    Eigen::Vector3d centroid;
    Eigen::Vector3d normal;  ///< unit, out of the body into the water
    double area;             ///< m^2
};

/// The part of `surface` (object space placed by `toWater`: water frame, y up, free surface
/// y = 0) strictly below the free surface: every triangle clipped at y = 0, the part below kept.
/// Triangles thinner than `minArea` (m^2) after clipping are dropped (they carry no force).
std::vector<RadiationPanel> wettedPanels(const TriangleMesh& surface,
                                         const Eigen::Affine3d& toWater, double minArea = 1e-12);

/// The panels split at edge midpoints until no edge is longer than maxEdge (m): a coarse
/// mesh (a box of 12 triangles) needs it before it resolves any flow.
std::vector<RadiationPanel> refinedPanels(const std::vector<RadiationPanel>& panels,
                                          double maxEdge);

/// The panels halved at their longest edge's midpoint until no edge is longer than maxEdge (m):
/// a long thin face (the 1 x 0.25 m side of a box) is cut across its length only, where
/// refinedPanels cuts every edge as often as the longest needs (64 panels for that face's
/// triangle at 0.2 m, here 12). Stops once more than `limit` panels are made.
std::vector<RadiationPanel> bisectedPanels(const std::vector<RadiationPanel>& panels,
                                           double maxEdge,
                                           std::size_t limit = static_cast<std::size_t>(-1));

/// `mesh` re-made at about `cell` (m) where it is finer: vertex clustering on a grid of that
/// size (vertices welded by position first), each cluster at its vertices' mean; a triangle
/// whose corners share a cluster is dropped, and two that meet the same clusters the other way
/// round cancel. What the mesh enclosed stays enclosed (a closed mesh stays closed, so its
/// waterline after clipping closes and gets its lid), slightly smaller (the means lie inside a
/// convex surface). A fine mesh (a 4000-triangle sphere) then costs the panel method what its
/// shape needs rather than what its tessellation has (docs/radiation.md "Coarser panels for
/// fine meshes").
TriangleMesh clusteredMesh(const TriangleMesh& mesh, double cell);

/// The interior waterplane of the wetted panels (the part of y = 0 their waterline encloses) as
/// panels no longer than about `maxEdge` (m; 0: one and a half times the waterline's mean edge),
/// normals up. A loop that is star-shaped about its centroid gets rings of panels about it,
/// another is ear-clipped and split. Star-shaped lids stop half a waterline edge short of the
/// waterline and have at most about half as many panels as `wetted` (fewer, longer rings); an
/// ear-clipped loop with the automatic edge is split no finer than its share by area of that
/// bound (longer panels, down to the ear-clipped triangles themselves). A
/// loop that runs the other way round (an opening in the waterplane, a moonpool) or a waterline
/// that does not close gets none. Empty when no panel edge lies on y = 0.
std::vector<RadiationPanel> waterplaneLid(const std::vector<RadiationPanel>& wetted,
                                          double maxEdge = 0);

/// Volume below y = 0 enclosed by the wetted panels and the waterplane (m^3): the divergence
/// theorem on (0, y, 0), whose flux through the waterplane vanishes.
double wettedVolume(const std::vector<RadiationPanel>& panels);

/// The height to raise (or lower, negative) `surface`, placed by `toWater`, so that it
/// displaces `volume` (m^3): bisection on wettedVolume (orientation kept: upright trim and
/// heel as placed). `volume` must lie between 0 and the enclosed volume.
double equilibriumHeight(const TriangleMesh& surface, const Eigen::Affine3d& toWater,
                         double volume);

struct RadiationSettings {
    double gravity = 9.81;  ///< m/s^2
    double density = 1025;  ///< kg/m^3
    /// Source panels closer than this many times their longest edge to the field point (or to
    /// its mirror image in the free surface) get subdivided 3-point rules for the wave part;
    /// farther ones one point.
    double nearFactor = 3.0;
    /// Sources on the interior waterplane (waterplaneLid) that remove the irregular frequencies
    /// at finite frequency; off, the body's panels alone.
    bool irregularFrequencyLid = true;
    /// Threads that assemble the influence matrices (rows handed out one at a time; the results
    /// are the same for any count). 0: std::thread::hardware_concurrency().
    unsigned threads = 0;
};

/// A(omega) and B(omega) at one frequency. Units: kg, kg m, kg m^2 (A); kg/s, kg m/s,
/// kg m^2/s (B), forces and moments about the reference point.
struct RadiationCoefficients {
    double omega = 0;  ///< rad/s
    Matrix6d addedMass = Matrix6d::Zero();
    Matrix6d damping = Matrix6d::Zero();
};

/// The solver for one wetted surface: the frequency-independent Rankine influences are computed
/// once, each frequency then adds the wave part and solves a complex dense system (N panels:
/// O(N^2) memory, O(N^3) per frequency).
class RadiationSolver {
public:
    /// `reference`: the point the moments are about (the centre of mass), water frame, m.
    RadiationSolver(std::vector<RadiationPanel> panels, const Eigen::Vector3d& reference,
                    RadiationSettings settings = {});

    /// A and B at omega > 0 (rad/s).
    RadiationCoefficients at(double omega) const;
    /// lim omega -> infinity of A(omega) (B vanishes there).
    Matrix6d infiniteFrequencyAddedMass() const;

    std::size_t panelCount() const { return panels_.size(); }
    const std::vector<RadiationPanel>& panels() const { return panels_; }
    /// The lid's panels (empty when settings.irregularFrequencyLid is off or the body does not
    /// pierce the surface).
    const std::vector<RadiationPanel>& lidPanels() const { return lid_; }

private:
    /// Solve for the source strengths of the six modes and integrate -rho phi n over the
    /// surface, given the potential and normal-velocity influence matrices. `system` has a row
    /// per unknown (body panels, then lid panels); `potential` the body's rows.
    Eigen::Matrix<std::complex<double>, 6, 6> forces(const Eigen::MatrixXcd& potential,
                                                     const Eigen::MatrixXcd& system) const;

    std::vector<RadiationPanel> panels_;
    std::vector<RadiationPanel> lid_;
    std::vector<RadiationPanel> sources_;  ///< panels_ then lid_
    RadiationSettings settings_;
    Eigen::Matrix<double, Eigen::Dynamic, 6> modeNormals_;  ///< generalised normal n_j per panel
    /// Integral of 1/r over source panel j averaged over field panel i, and its d/dn_i; rows
    /// and columns: sources_ (the normal rows of the lid are unused).
    Eigen::MatrixXd directPotential_, directNormal_;
    Eigen::MatrixXd imagePotential_, imageNormal_;  ///< the same for 1/r' (mirror in y = 0)
    /// A source panel near a field panel's centroid or its image: the frequency-independent
    /// integrals over the source of the wave part's singular terms (radiation.cpp, at()).
    struct NearSource {
        Eigen::Index source = 0;
        double logIntegral = 0;                                 ///< int ln(r' + d) dS, m^2 ln m
        double distanceIntegral = 0;                            ///< int r' dS, m^3
        Eigen::Vector3d logGradient = Eigen::Vector3d::Zero();  ///< int grad_x ln(r' + d) dS
        Eigen::Vector3d distanceGradient = Eigen::Vector3d::Zero();  ///< int grad_x r' dS
    };
    std::vector<std::vector<NearSource>> near_;  ///< per row of sources_, by source index
    bool isFar(Eigen::Index field, Eigen::Index source) const;
};

/// The wave part of the deep-water Green function, nondimensional: with X = K R (horizontal
/// distance) and Y = -K (y + eta) >= 0 (depth of the source and field points below the
/// surface added up), value = PV int_0^inf exp(-m Y) J0(m X) / (m - 1) dm and its derivatives
/// in X and Y; the full function is G = 1/r + 1/r' + 2 K value + i 2 pi K exp(-Y) J0(X).
struct WaveGreen {
    double value = 0, dX = 0, dY = 0;
};
WaveGreen waveGreen(double X, double Y);
/// waveGreen from a table (cubic interpolation of what is left after the logarithm and cone of
/// the origin, filled on first use, in 1/16 steps below X, Y = 4 and 1/4 steps up to X = 96,
/// Y = 48; waveGreen itself outside): tens of nanoseconds rather than microseconds. Its error
/// (docs/radiation.md "The wave kernel's table"): below 2e-3 in value near the origin and below
/// 5e-4 elsewhere, where |F| is about 1 to 5.
WaveGreen tabulatedWaveGreen(double X, double Y);

/// Struve functions H0 and H1 (series below 16, asymptotic expansion of H - Y above).
double struveH0(double x);
double struveH1(double x);

/// Integral of 1/|r - s| over the flat triangle (s on it) and its gradient in r: exact
/// (Wilton et al. 1984, IEEE Trans. Antennas Propag. 32(3)). r must not lie on an edge.
struct RankineIntegral {
    double potential = 0;
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
};
RankineIntegral rankineTriangle(const std::array<Eigen::Vector3d, 3>& triangle,
                                const Eigen::Vector3d& r);

}  // namespace plimsoll
