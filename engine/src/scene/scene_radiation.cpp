// Radiation of a scene body (scene_radiation.h).
#include "plimsoll/scene/scene_radiation.h"

#include "plimsoll/core/hash.h"
#include "plimsoll/scene/scene_hydrostatics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace plimsoll {

namespace {

/// Bumped when the computation changes what it produces from the same inputs.
constexpr int kRadiationVersion = 7;

/// A wetted mesh whose mean longest panel edge is under this share of the panel edge is
/// re-panelled by clustering on cells of kCoarsenCell panel edges.
constexpr double kCoarsenBelow = 0.5;
constexpr double kCoarsenCell = 1.0 / 1.5;

/// The mesh as the panel method takes it, and the mass that floats.
struct RestInput {
    const TriangleMesh* mesh = nullptr;
    double mass = 0;
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();
};

Result<RestInput> restInput(const SceneBody& body, const MediumDesc& medium) {
    Result<FloatingBody> floating = floatingBodyOf(body, medium);
    if (!floating) return floating.error();
    return RestInput{body.parts.mesh.get(), floating->body.mass, floating->body.centerOfMass};
}

}  // namespace

RadiationDesc resolvedRadiationDesc(const RadiationDesc& desc, double restVolume, double gravity) {
    RadiationDesc r = desc;
    const double size = std::cbrt(std::max(restVolume, 0.0));
    // cbrt(V) / 2: a 1 m cube of density 250 gets 272 panels (+120 on the lid), within 2% of the
    // 1088-panel solution where its A and B matter (docs/radiation.md, "The default panel edge");
    // cbrt(V) / 2.5 made 656 and took four times as long for no better agreement.
    if (!(r.panelEdge > 0)) r.panelEdge = size / 2.0;
    if (!(r.minFrequency > 0) || !(r.maxFrequency > 0)) {
        const double length = size / 2;
        r.minFrequency = std::sqrt(0.05 * gravity / length);
        r.maxFrequency = std::sqrt(5.0 * gravity / length);
    }
    return r;
}

std::string radiationKey(const SceneBody& body, const RadiationDesc& desc, const MediumDesc& medium,
                         const Eigen::Vector3d& gravity) {
    std::uint64_t h = kFnv1aBasis;
    auto add = [&h](double v) { h = fnv1a(h, &v, sizeof v); };
    add(kRadiationVersion);
    if (body.parts.mesh) {
        for (const Eigen::Vector3d& p : body.parts.mesh->positions)
            h = fnv1a(h, p.data(), 3 * sizeof(double));
        for (const Triangle& t : body.parts.mesh->triangles)
            h = fnv1a(h, t.data(), sizeof(Triangle));
    }
    if (Result<RestInput> rest = restInput(body, medium)) {
        add(rest->mass);
        for (int k = 0; k < 3; ++k) add(rest->centerOfMass[k]);
    }
    add(desc.panelEdge);
    add(desc.frequencies);
    add(desc.minFrequency);
    add(desc.maxFrequency);
    add(medium.density);
    add(gravity.norm());
    return hashText(h);
}

std::optional<std::string> defaultRadiationInapplicable(const SceneBody& body,
                                                        const MediumDesc& medium) {
    if (body.desc.deforms()) return "a deforming body";
    // A liquid: water is 1000 kg/m^3, the lightest liquids about 600; air is 1.2.
    if (medium.density < 100) return "the medium is not a liquid: no free surface";
    if (!body.parts.mesh) return "no mesh";
    Result<RestInput> rest = restInput(body, medium);
    if (!rest) return rest.error().message;
    const TriangleMesh& mesh = *rest->mesh;
    double highest = -std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : mesh.positions) highest = std::max(highest, p.y());
    const double enclosed = wettedVolume(
        wettedPanels(mesh, Eigen::Affine3d(Eigen::Translation3d(0, -highest - 1.0, 0))));
    const double restVolume = rest->mass / medium.density;
    if (!(restVolume > 0) || !(restVolume < enclosed)) return "the body does not float";
    return std::nullopt;
}

Result<RestRadiationSurface> restRadiationSurface(const SceneBody& body, const RadiationDesc& desc,
                                                  const MediumDesc& medium,
                                                  const Eigen::Vector3d& gravity,
                                                  unsigned threads) {
    const std::string label = body.label + ": radiation: ";
    const double g = gravity.norm();
    if (!(g > 0))
        return makeError(ErrorKind::invalidArgument, label + "without gravity nothing floats");
    Result<RestInput> rest = restInput(body, medium);
    if (!rest) return withContext(label, rest.error());
    RestRadiationSurface out;
    out.restVolume = rest->mass / medium.density;
    const TriangleMesh& mesh = *rest->mesh;
    // The enclosed volume: the wetted volume with the whole body under water.
    double highest = -std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : mesh.positions) highest = std::max(highest, p.y());
    const double enclosed = wettedVolume(
        wettedPanels(mesh, Eigen::Affine3d(Eigen::Translation3d(0, -highest - 1.0, 0))));
    if (!(out.restVolume > 0) || !(out.restVolume < enclosed)) {
        std::ostringstream m;
        m << label << "the body does not float (displacement at rest " << out.restVolume
          << " m^3, enclosed volume " << enclosed << " m^3): no waterline to radiate from";
        return makeError(ErrorKind::invalidArgument, m.str());
    }
    out.resolved = resolvedRadiationDesc(desc, out.restVolume, g);
    out.restHeight = equilibriumHeight(mesh, Eigen::Affine3d::Identity(), out.restVolume);
    Eigen::Affine3d atRest(Eigen::Translation3d(0, out.restHeight, 0));
    // Slivers the waterline cuts off a triangle carry no force and spoil the collocation (a
    // sphere's equator row 0.1 mm under water made 16 of them and moved its heave damping 5%).
    const double minArea = 1e-4 * std::pow(out.restVolume, 2.0 / 3.0);
    std::vector<RadiationPanel> wetted = wettedPanels(mesh, atRest, minArea);
    const double edge = out.resolved.panelEdge;
    // A mesh much finer than the panel edge (a 4000-triangle sphere, a detailed hull) is
    // re-made at about the edge, whole, then raised to the same displacement and clipped: its
    // shape, not its tessellation, sets the cost (clusteredMesh; docs/radiation.md "Coarser
    // panels for fine meshes").
    double meanEdge = 0;
    for (const RadiationPanel& p : wetted) {
        meanEdge += std::max({(p.vertices[1] - p.vertices[0]).norm(),
                              (p.vertices[2] - p.vertices[1]).norm(),
                              (p.vertices[0] - p.vertices[2]).norm()});
    }
    if (!wetted.empty()) meanEdge /= static_cast<double>(wetted.size());
    if (meanEdge < kCoarsenBelow * edge) {
        const TriangleMesh coarse = clusteredMesh(mesh, kCoarsenCell * edge);
        atRest = Eigen::Translation3d(
            0, equilibriumHeight(coarse, Eigen::Affine3d::Identity(), out.restVolume), 0);
        wetted = wettedPanels(coarse, atRest, minArea);
    }
    std::vector<RadiationPanel> panels = bisectedPanels(wetted, edge, kMaxRadiationPanels);
    if (const std::size_t count = panels.size(); count > kMaxRadiationPanels) {
        std::ostringstream m;
        m << label << "the wetted surface makes more than " << count - 1 << " panels at panel_edge "
          << edge << " m, more than the limit kMaxRadiationPanels = " << kMaxRadiationPanels
          << ": give a longer panel_edge"
          << (wetted.size() > kMaxRadiationPanels ? " and a coarser mesh" : "");
        return makeError(ErrorKind::limit, m.str());
    }
    out.solver.emplace(
        std::move(panels), atRest * rest->centerOfMass,
        RadiationSettings{.gravity = g, .density = medium.density, .threads = threads});
    return out;
}

Result<BodyRadiation> computeBodyRadiation(const SceneBody& body, const RadiationDesc& desc,
                                           const MediumDesc& medium, const Eigen::Vector3d& gravity,
                                           const ProgressCallback& progress, unsigned threads) {
    Result<RestRadiationSurface> surface =
        restRadiationSurface(body, desc, medium, gravity, threads);
    if (!surface) return surface.error();
    const RadiationSolver& solver = *surface->solver;
    const RadiationDesc& resolved = surface->resolved;
    BodyRadiation out;
    out.restVolume = surface->restVolume;
    out.restHeight = surface->restHeight;
    out.panelEdge = resolved.panelEdge;
    out.panelCount = solver.panelCount();
    const int n = resolved.frequencies;
    for (int k = 0; k < n; ++k) {
        const double omega =
            resolved.minFrequency *
            std::pow(resolved.maxFrequency / resolved.minFrequency, k / double(n - 1));
        out.coefficients.push_back(solver.at(omega));
        if (progress) progress((k + 1.0) / (n + 1.0));
    }
    out.addedMassInfinity = solver.infiniteFrequencyAddedMass();
    if (progress) progress(1.0);
    fitRadiationModel(out);
    return out;
}

void fitRadiationModel(BodyRadiation& radiation) {
    radiation.model = cumminsModel(radiation.coefficients, radiation.addedMassInfinity);
    // A rotation that displaces almost no water (a sphere's about its centre, a body of
    // revolution's yaw) makes no waves; what the panels give for it is their facets' error (the
    // sample sphere: A and B of roll about 1e-3 of rho V L^2, where its translations have 0.3 to
    // 0.8), and that error slowed the settling of neutral_ball. Such a mode gets none.
    double translation = 0;
    for (int i = 0; i < 3; ++i)
        translation = std::max(translation, std::abs(radiation.addedMassInfinity(i, i)));
    const double L = std::cbrt(radiation.restVolume);
    const double negligible = kNegligibleRotationalRadiation * translation * L * L;
    for (int mode = 3; mode < 6; ++mode) {
        double largest = std::abs(radiation.addedMassInfinity(mode, mode));
        for (const RadiationCoefficients& c : radiation.coefficients) {
            largest = std::max({largest, std::abs(c.addedMass(mode, mode)),
                                c.omega > 0 ? std::abs(c.damping(mode, mode)) / c.omega : 0.0});
        }
        if (largest >= negligible) continue;
        radiation.model.addedMassInfinity.row(mode).setZero();
        radiation.model.addedMassInfinity.col(mode).setZero();
        radiation.model.memory[mode].clear();
    }
}

}  // namespace plimsoll
