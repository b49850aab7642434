// Layers and masks of painted maps (document/layers.h): the flattening against blends computed
// by hand, every layer operation undone and redone byte for byte, strokes on layers and masks,
// the stack saved beside the map and read back, the map file equal to the flattening, and the
// same operations from an edit script. Also the "New map" data-loss regression: replacing a
// saved map is undone back to the saved pixels.
#include "test_support.h"
#include "editor/document_test_support.h"

#include "document/command.h"
#include "document/document.h"
#include "document/layers.h"
#include "document/script.h"
#include "document/smart_mask.h"

#include "plimsoll/surface/painted_map.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/bake/bake.h"

#include <gtest/gtest.h>

#include <fstream>

namespace plimsoll::editor {
namespace test_editor_layers {
namespace {

namespace fs = std::filesystem;
using test::executeOrFail;
using test::openOrFail;

constexpr int kSize = 64;

/// A project with one body (the unit sphere, solid + shell) in a fresh folder.
fs::path sphereProject(const std::string& name) {
    const fs::path dir = test::scratchFolder("layers_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path path = dir / "layers.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "ball", "mesh": ")"
        << test::assetPath("sphere.obj").string()
        << R"(", "material": {"density": 500, "shell": {"surface_density": 10}}}]})";
    return path;
}

constexpr MapChannel kPerm = MapChannel::Permeability;

/// The document's map and layers as bytes: what "byte for byte" compares.
std::string snapshot(const Document& d) {
    std::string bytes;
    if (const PaintedMap* map = d.map(0, kPerm)) bytes += encodePaintedMapPng16(*map);
    bytes += "|";
    if (const LayerStack* stack = d.layers(0, kPerm)) bytes += layerStackToJson(*stack);
    return bytes;
}

/// The document's bytes after each step of a test: every step must change them, and the map
/// stays the flattening of its stack; undoAll walks back through them, redoAll forward again.
class UndoTrail {
public:
    explicit UndoTrail(Document& d) : d_(d), states_{snapshot(d)} {}

    void step(Result<std::unique_ptr<Command>> command) {
        executeOrFail(d_, std::move(command));
        states_.push_back(snapshot(d_));
        EXPECT_TRUE(states_.back() != states_[states_.size() - 2])
            << d_.undoName() << " changed nothing";
        ASSERT_TRUE(d_.layers(0, kPerm));
        EXPECT_EQ(encodePaintedMapPng16(*d_.map(0, kPerm)),
                  encodePaintedMapPng16(flattenLayers(*d_.layers(0, kPerm))));
    }
    void undoAll() {
        for (std::size_t i = states_.size() - 1; i > 0; --i) {
            ASSERT_TRUE(d_.undo());
            EXPECT_TRUE(snapshot(d_) == states_[i - 1]) << "undo to state " << i - 1;
        }
    }
    void redoAll() {
        for (std::size_t i = 1; i < states_.size(); ++i) {
            ASSERT_TRUE(d_.redo());
            EXPECT_TRUE(snapshot(d_) == states_[i]) << "redo to state " << i;
        }
    }

private:
    Document& d_;
    std::vector<std::string> states_;
};

/// A stroke on the sphere (radius 0.5) through its +x pole (object space).
std::vector<Eigen::Vector3d> poleStroke() {
    return {{0.5, 0, 0}, Eigen::Vector3d(0.95, 0.3, 0).normalized() * 0.5};
}

TEST(EditorLayers, BlendModesMatchTheirFormulas) {
    // below c = 0.6, layer v = 0.5, computed by hand.
    const float c = 0.6f, v = 0.5f;
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Normal, c, v), 0.5f);
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Multiply, c, v), 0.3f);
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Add, c, v), 1.0f);  // 1.1 clamped
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Subtract, c, v), 0.1f);
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Screen, c, v), 0.8f);  // 1 - 0.4 * 0.5
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Lighten, c, v), 0.6f);
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Darken, c, v), 0.5f);
    EXPECT_FLOAT_EQ(blendValue(BlendMode::Subtract, 0.2f, 0.5f), 0.0f);  // clamped
    for (int i = 0; i < kBlendModeCount; ++i) {
        const auto mode = static_cast<BlendMode>(i);
        EXPECT_EQ(parseBlendMode(blendModeName(mode)), mode);
    }
}

TEST(EditorLayers, FlattenEqualsHandComputedStack) {
    // Two pixels. Base paint layer [0.2, 0.8]; a fill 0.5 multiply at opacity 0.5; a paint
    // layer [1, 1] screen with coverage [1, 0.25] and a mask [0.5, 1]; a hidden fill 0.
    LayerStack stack;
    stack.width = 2;
    stack.height = 1;
    MapLayer base;
    base.name = "Base";
    base.pixels = std::make_shared<PaintedMap>(uniformMap(2, 1, 0));
    base.pixels->values = {0.2f, 0.8f};
    MapLayer fill;
    fill.kind = LayerKind::Fill;
    fill.fillValue = 0.5f;
    fill.blend = BlendMode::Multiply;
    fill.opacity = 0.5f;
    MapLayer top;
    top.pixels = std::make_shared<PaintedMap>(uniformMap(2, 1, 1));
    top.blend = BlendMode::Screen;
    top.coverage = std::make_shared<PaintedMap>(uniformMap(2, 1, 0));
    top.coverage->values = {1.0f, 0.25f};
    top.mask = std::make_shared<PaintedMap>(uniformMap(2, 1, 0));
    top.mask->values = {0.5f, 1.0f};
    MapLayer hidden;
    hidden.kind = LayerKind::Fill;
    hidden.fillValue = 0.0f;
    hidden.visible = false;
    stack.layers = {base, fill, top, hidden};
    ASSERT_TRUE(checkStack(stack).ok());
    // Pixel 0: 0.2 -> multiply 0.1, half way: 0.15 -> screen(0.15, 1) = 1 at alpha 0.5: 0.575.
    // Pixel 1: 0.8 -> multiply 0.4, half way: 0.6 -> screen 1 at alpha 0.25: 0.7.
    const PaintedMap flat = flattenLayers(stack);
    ASSERT_EQ(flat.values.size(), 2u);
    EXPECT_NEAR(flat.values[0], 0.575f, 1e-6);
    EXPECT_NEAR(flat.values[1], 0.7f, 1e-6);
}

TEST(EditorLayers, EveryOperationUndoesAndRedoesByteForByte) {
    auto d = openOrFail(sphereProject("undo"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.25, ""));
    UndoTrail trail(*d);
    const auto step = [&](Result<std::unique_ptr<Command>> command) {
        trail.step(std::move(command));
    };
    Brush brush;
    brush.radius = 0.3;
    brush.value = 0.9;
    step(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "wet", 0.75));  // 2 layers
    step(makeAddMaskCommand(*d, 0, kPerm, 1, 0.0));                         // fill hidden
    step(makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {1, LayerPart::Mask}));
    step(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "", 1.0));  // clear: same map
    step(makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {2, LayerPart::Pixels}));
    LayerEdit edit;
    edit.opacity = 0.5;
    edit.blend = BlendMode::Multiply;
    step(makeSetLayerCommand(*d, 0, kPerm, 2, edit));
    step(makeMoveLayerCommand(*d, 0, kPerm, 2, 0));
    LayerEdit hide;
    hide.visible = false;
    step(makeSetLayerCommand(*d, 0, kPerm, 1, hide));
    step(makeRemoveMaskCommand(*d, 0, kPerm, 2));
    step(makeRemoveLayerCommand(*d, 0, kPerm, 0));

    trail.undoAll();
    EXPECT_FALSE(d->layers(0, kPerm)) << "the first layer's undo gives back the plain map";
    trail.redoAll();
}

TEST(EditorLayers, PaintLayerIsClearUntilPaintedAndMasksHide) {
    auto d = openOrFail(sphereProject("paint"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.25, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "top", 1.0));
    // The map became the Base layer, at the 16 bits of the files.
    const float base = quantize16(0.25f);
    const std::vector<float> plain(static_cast<std::size_t>(kSize) * kSize, base);
    EXPECT_EQ(d->map(0, kPerm)->values, plain) << "a new paint layer is clear";

    Brush brush;
    brush.radius = 0.3;
    brush.value = 1.0;
    brush.strength = 0.5;
    brush.falloff = Falloff::Constant;
    // Without a layer named, strokes go to the top paint layer.
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke()));
    const LayerStack& stack = *d->layers(0, kPerm);
    std::size_t painted = 0;
    for (std::size_t i = 0; i < plain.size(); ++i) {
        const float coverage = stack.layers[1].coverage->values[i];
        const float expected = base + (1.0f - base) * coverage;
        ASSERT_NEAR(d->map(0, kPerm)->values[i], expected, 1e-6);
        if (coverage > 0) {
            // Half strength on an empty pixel: the full value at half coverage.
            EXPECT_EQ(coverage, quantize16(0.5f));
            EXPECT_FLOAT_EQ(stack.layers[1].pixels->values[i], 1.0f);
            ++painted;
        }
    }
    EXPECT_GT(painted, 10u);

    // Erasing a layer lowers its coverage back to clear.
    Brush erase = brush;
    erase.mode = BrushMode::Erase;
    erase.strength = 1.0;
    erase.radius = 0.6;
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, erase, poleStroke()));
    EXPECT_EQ(d->map(0, kPerm)->values, plain);

    // A fill layer cannot be painted, only its mask; a mask of 0 hides it.
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "", 0.5));
    EXPECT_FALSE(makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {2, LayerPart::Pixels}).ok());
    EXPECT_FALSE(makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {2, LayerPart::Mask}).ok());
    executeOrFail(*d, makeAddMaskCommand(*d, 0, kPerm, 2, 0.0));
    EXPECT_EQ(d->map(0, kPerm)->values, plain);
    executeOrFail(*d, makeFillAllCommand(*d, 0, kPerm, 1.0, 0.5, {2, LayerPart::Mask}));
    const float mask = quantize16(0.5f);
    for (std::size_t i = 0; i < plain.size(); ++i) {
        ASSERT_NEAR(d->map(0, kPerm)->values[i], base + (0.5f - base) * mask, 1e-6);
    }
}

TEST(EditorLayers, SmartMasksFollowTheWaterlineTheDepthAndTheFacing) {
    // The sphere (radius 0.5) at its starting pose, raised 0.2 m: the water at 0 cuts it
    // 0.2 m below its centre.
    auto d = openOrFail(sphereProject("smart"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.0, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "wet", 1.0));
    Result<std::shared_ptr<const PaintSurface>> surface = d->paintSurface(0, kPerm);
    ASSERT_TRUE(surface.ok()) << surface.error().message;
    const PaintSurface& grid = **surface;
    SmartMask mask;
    mask.pose.translation = Eigen::Vector3d(0, 0.2, 0);
    const std::string before = snapshot(*d);
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    EXPECT_EQ(d->undoName(), "Smart mask: below the waterline");
    const PaintedMap& below = *d->layers(0, kPerm)->layers[1].mask;
    // Every pixel whose pieces of surface all lie well below the water is 1, well above 0:
    // the fill shows exactly on the wet part of the hull.
    std::vector<double> lowest(below.values.size(), 1e9), highest(below.values.size(), -1e9);
    for (std::size_t k = 0; k < grid.sampleCount(); ++k) {
        const double y = grid.position[k].y() + 0.2;
        lowest[grid.pixel[k]] = std::min(lowest[grid.pixel[k]], y);
        highest[grid.pixel[k]] = std::max(highest[grid.pixel[k]], y);
    }
    std::size_t wet = 0, dry = 0;
    for (std::size_t i = 0; i < below.values.size(); ++i) {
        if (highest[i] < -1e-3) {
            EXPECT_EQ(below.values[i], 1.0f) << i;
            ++wet;
        } else if (lowest[i] > 1e-3 && lowest[i] < 1e9) {
            EXPECT_EQ(below.values[i], 0.0f) << i;
            ++dry;
        }
        EXPECT_NEAR(d->map(0, kPerm)->values[i], below.values[i], 1e-6);  // 0 under the fill
    }
    EXPECT_GT(wet, 100u);
    EXPECT_GT(dry, 100u);

    // By depth: 0 at the water, 1 from 0.5 m down, linear between (the pixel's mean).
    mask.kind = SmartMask::Kind::Depth;
    mask.depth = 0.5;
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    const PaintedMap& depth = *d->layers(0, kPerm)->layers[1].mask;
    for (std::size_t k = 0; k < grid.sampleCount(); ++k) {
        const std::size_t i = grid.pixel[k];
        if (highest[i] - lowest[i] > 1e-6 || highest[i] > 0) continue;  // one depth, wet
        EXPECT_NEAR(depth.values[i], std::min(1.0, -lowest[i] / 0.5), 1e-4) << i;
    }
    // Facing up: the normal's rise, 0 on every face turned down.
    mask.kind = SmartMask::Kind::Facing;
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    const PaintedMap& up = *d->layers(0, kPerm)->layers[1].mask;
    for (std::size_t k = 0; k < grid.sampleCount(); ++k) {
        if (grid.normal[k].y() < -0.05f) EXPECT_EQ(up.values[grid.pixel[k]], 0.0f);
    }
    EXPECT_FALSE(makeSmartMaskCommand(*d, 0, kPerm, 7, mask).ok());  // no such layer
    // Three steps, undone back to the layer without a mask.
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(d->undo());
    EXPECT_EQ(snapshot(*d), before);
    // The script verb: the body at its starting pose (0.2 m up in the test's pose, at the
    // origin in the project) against the project's still water at 0.
    const nlohmann::json script = nlohmann::json::parse(
        R"([{"op": "smart_mask", "layer": 1, "kind": "facing", "direction": [0, -1, 0]}])");
    Result<nlohmann::json> ran = runEditScript(*d, script);
    ASSERT_TRUE(ran.ok()) << ran.error().message;
    SmartMask down;
    down.kind = SmartMask::Kind::Facing;
    down.direction = -Eigen::Vector3d::UnitY();
    PaintedMap expected = smartMaskImage(grid, down);
    for (float& v : expected.values) v = quantize16(v);
    EXPECT_EQ(d->layers(0, kPerm)->layers[1].mask->values, expected.values);
    EXPECT_FALSE(runEditScript(*d, nlohmann::json::parse(
                                       R"([{"op": "smart_mask", "layer": 1, "kind": "wet"}])"))
                     .ok());
}

/// A project with one solid body of the mesh at `mesh` in a fresh folder, its surface as it is
/// (no cap closes a hollow that would hold water: the dent below is one).
fs::path meshProject(const std::string& name, const fs::path& mesh) {
    const fs::path dir = test::freshFolder("layers", name);
    const fs::path path = dir / "mesh.plim.json";
    std::ofstream(path)
        << R"({"schema_version": 1, "name": "t", "bodies": [{"name": "b", "mesh": ")"
        << mesh.string() << R"(", "openings": "none", "material": {"density": 500}}]})";
    return path;
}

/// Distance from p to the segment a..b.
double segmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b) {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (a + t * (b - a) - p).norm();
}

TEST(EditorLayers, CurvatureIsOneOverTheRadiusOnASphere) {
    // The sample sphere (radius 0.5, edges about 0.05 m long) measured over balls of 0.15 m:
    // the mean curvature 1/R = 2 at every sample, and the curvature mask one value everywhere.
    auto d = openOrFail(meshProject("curv_sphere", test::assetPath("sphere.obj")));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.0, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "edges", 1.0));
    Result<std::shared_ptr<const PaintSurface>> surface = d->paintSurface(0, kPerm);
    ASSERT_TRUE(surface.ok()) << surface.error().message;
    const PaintSurface& grid = **surface;
    const std::vector<double> h = meanCurvatureAt(*d->assets(0).mesh, grid.position, 0.15);
    ASSERT_EQ(h.size(), grid.sampleCount());
    for (std::size_t k = 0; k < h.size(); ++k) ASSERT_NEAR(h[k], 2.0, 0.1) << k;

    SmartMask mask;
    mask.kind = SmartMask::Kind::Curvature;
    mask.radius = 0.15;
    mask.fullCurvature = 4;  // 2 / 4: every covered pixel 0.5
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    EXPECT_EQ(d->undoName(), "Smart mask: curvature");
    const PaintedMap& m = *d->layers(0, kPerm)->layers[1].mask;
    std::vector<bool> covered(m.values.size(), false);
    for (std::uint32_t i : grid.pixel) covered[i] = true;
    for (std::size_t i = 0; i < m.values.size(); ++i) {
        if (covered[i]) ASSERT_NEAR(m.values[i], 0.5, 0.025) << i;
    }
    // A convex mesh has no cavity.
    mask.kind = SmartMask::Kind::Cavity;
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    for (float v : d->layers(0, kPerm)->layers[1].mask->values) ASSERT_EQ(v, 0.0f);
    ASSERT_TRUE(d->undo());
    ASSERT_TRUE(d->undo());
    EXPECT_FALSE(d->layers(0, kPerm)->layers[1].mask);
    mask.radius = 0;
    EXPECT_FALSE(makeSmartMaskCommand(*d, 0, kPerm, 1, mask).ok());
}

TEST(EditorLayers, CurvatureMarksABoxsEdgesAndNotItsFaces) {
    // The sample box (1 x 0.5 x 0.25 m). A right-angle edge turns pi/2; a point at distance
    // s < r from it, farther than r from the corners, has the edge's chord 2 sqrt(r^2 - s^2)
    // inside the ball, so the edge gives H = (pi/2) sqrt(r^2 - s^2) / (pi r^2) (near a corner
    // two edges may reach the ball: their shares add); a point farther than r from every edge
    // has 0.
    const double r = 0.05;
    auto d = openOrFail(meshProject("curv_box", test::assetPath("box.obj")));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.0, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "edges", 1.0));
    Result<std::shared_ptr<const PaintSurface>> surface = d->paintSurface(0, kPerm);
    ASSERT_TRUE(surface.ok()) << surface.error().message;
    const PaintSurface& grid = **surface;
    const Eigen::Vector3d half(0.5, 0.25, 0.125);
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges;
    std::vector<Eigen::Vector3d> corners;
    for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d c((i & 1 ? 1 : -1) * half.x(), (i & 2 ? 1 : -1) * half.y(),
                                (i & 4 ? 1 : -1) * half.z());
        corners.push_back(c);
        for (int axis = 0; axis < 3; ++axis) {
            if (!(i & (1 << axis))) continue;
            Eigen::Vector3d o = c;
            o[axis] = -o[axis];
            edges.emplace_back(o, c);
        }
    }
    ASSERT_EQ(edges.size(), 12u);
    const std::vector<double> h = meanCurvatureAt(*d->assets(0).mesh, grid.position, r);
    std::size_t onEdges = 0, onFaces = 0;
    for (std::size_t k = 0; k < h.size(); ++k) {
        const Eigen::Vector3d p = grid.position[k].cast<double>();
        double edge = 1e9, corner = 1e9, expected = 0;
        for (const auto& [a, b] : edges) {
            const double s = segmentDistance(p, a, b);
            edge = std::min(edge, s);
            expected += std::sqrt(std::max(0.0, r * r - s * s)) / (2 * r * r);
        }
        for (const Eigen::Vector3d& c : corners) corner = std::min(corner, (p - c).norm());
        if (edge > r + 1e-6) {
            ASSERT_EQ(h[k], 0.0) << k;
            ++onFaces;
        } else if (corner > r + 1e-6) {
            ASSERT_NEAR(h[k], expected, 1e-4) << k;
            ++onEdges;
        }
    }
    EXPECT_GT(onEdges, 100u);
    EXPECT_GT(onFaces, 100u);
    // The mask: full on the edges' lines, empty on the faces, nothing for the cavity.
    SmartMask mask;
    mask.kind = SmartMask::Kind::Curvature;
    mask.radius = r;
    mask.fullCurvature = 2.5;
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    const PaintedMap& m = *d->layers(0, kPerm)->layers[1].mask;
    PaintedMap expected = smartMaskImage(grid, mask, d->assets(0).mesh.get());
    for (float& v : expected.values) v = quantize16(v);
    EXPECT_EQ(m.values, expected.values);
    std::size_t full = 0, empty = 0;
    for (float v : m.values) {
        full += v == 1.0f;
        empty += v == 0.0f;
    }
    EXPECT_GT(full, 20u);
    EXPECT_GT(empty, 100u);
    const nlohmann::json script = nlohmann::json::parse(
        R"([{"op": "smart_mask", "layer": 1, "kind": "cavity", "radius": 0.05}])");
    Result<nlohmann::json> ran = runEditScript(*d, script);
    ASSERT_TRUE(ran.ok()) << ran.error().message;
    EXPECT_EQ(d->undoName(), "Smart mask: cavity");
    for (float v : d->layers(0, kPerm)->layers[1].mask->values) ASSERT_EQ(v, 0.0f);
}

TEST(EditorLayers, CavityMarksADentAndNothingElse) {
    // The sample sphere (R = 0.5) with its vertices above y = 0.3 mirrored in that plane: a
    // dimple, a sphere of radius R turned inside out (mean curvature -1/R = -2), inside the
    // ball. Its rim is a ridge (the surface rises to it from both sides): between the last ring
    // kept and the first mirrored one the surface turns convex by about 100 degrees.
    Result<TriangleMesh> loaded = loadMesh(test::assetPath("sphere.obj"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    TriangleMesh dented = std::move(loaded).value();
    // The ridge's two rings in the profile (radius from the axis, height).
    Eigen::Vector2d kept(0, -1), mirrored(0, 1);
    for (Eigen::Vector3d& v : dented.positions) {
        const Eigen::Vector2d profile(std::hypot(v.x(), v.z()), v.y());
        if (v.y() > 0.3) {
            if (v.y() < mirrored.y()) mirrored = profile;
            v.y() = 0.6 - v.y();
        } else if (v.y() > kept.y()) {
            kept = profile;
        }
    }
    mirrored.y() = 0.6 - mirrored.y();
    const fs::path dir = test::freshFolder("layers", "dent_mesh");
    ASSERT_TRUE(writeObj(dented, dir / "dented.obj").ok());
    auto d = openOrFail(meshProject("dent", dir / "dented.obj"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.0, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "dirt", 1.0));
    Result<std::shared_ptr<const PaintSurface>> surface = d->paintSurface(0, kPerm);
    ASSERT_TRUE(surface.ok()) << surface.error().message;
    const PaintSurface& grid = **surface;
    const double r = 0.1;
    const std::vector<double> h = meanCurvatureAt(*d->assets(0).mesh, grid.position, r);
    // Where a sample lies: 1 in the dimple, 2 on the sphere, both farther than r from the
    // ridge; 3 on the ridge; 0 near it.
    const auto placeOf = [&](const Eigen::Vector3d& p) {
        const Eigen::Vector2d profile(std::hypot(p.x(), p.z()), p.y());
        const double ridge = std::min((profile - kept).norm(), (profile - mirrored).norm());
        if (ridge < 0.01) return 3;
        if (ridge < r + 0.005) return 0;
        return p.norm() < 0.49 ? 1 : 2;
    };
    std::size_t counts[4] = {0, 0, 0, 0};
    for (std::size_t k = 0; k < h.size(); ++k) {
        const int place = placeOf(grid.position[k].cast<double>());
        ++counts[place];
        if (place == 1) ASSERT_NEAR(h[k], -2.0, 0.15) << k;
        if (place == 2) ASSERT_NEAR(h[k], 2.0, 0.15) << k;
        if (place == 3) ASSERT_GT(h[k], 3.0) << k;  // the ridge: curvature, not cavity
    }
    EXPECT_GT(counts[1], 20u);
    EXPECT_GT(counts[2], 200u);
    EXPECT_GT(counts[3], 5u);
    SmartMask mask;
    mask.kind = SmartMask::Kind::Cavity;
    mask.radius = r;
    mask.fullCurvature = 1;
    executeOrFail(*d, makeSmartMaskCommand(*d, 0, kPerm, 1, mask));
    const PaintedMap& m = *d->layers(0, kPerm)->layers[1].mask;
    // Each pixel's places as bits: the dimple's pixels are full, the sphere's (convex
    // everywhere, far from the ridge) empty.
    std::vector<int> where(m.values.size(), 0);
    for (std::size_t k = 0; k < grid.sampleCount(); ++k)
        where[grid.pixel[k]] |= 1 << placeOf(grid.position[k].cast<double>());
    std::size_t full = 0, empty = 0;
    for (std::size_t i = 0; i < m.values.size(); ++i) {
        if (where[i] == 1 << 1) {
            ASSERT_EQ(m.values[i], 1.0f) << i;
            ++full;
        } else if (where[i] == 1 << 2) {
            ASSERT_EQ(m.values[i], 0.0f) << i;
            ++empty;
        }
    }
    EXPECT_GT(full, 5u);
    EXPECT_GT(empty, 100u);
}

TEST(EditorLayers, HistoryNamesMaskStrokesAndPropertiesAsAPersonWould) {
    // The history said "Paint permeability" for a stroke on a mask and "Set
    // /bodies/0/material/density" for the inspector's density: a mask's strokes and fills now
    // say "mask", and a property edit names the body and the property.
    auto d = openOrFail(sphereProject("labels"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.25, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "top", 1.0));
    executeOrFail(*d, makeAddMaskCommand(*d, 0, kPerm, 1, 1.0));
    Brush brush;
    brush.radius = 0.3;
    brush.mode = BrushMode::Erase;
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {1, LayerPart::Mask}));
    EXPECT_EQ(d->undoName(), "Erase permeability mask");
    executeOrFail(*d, makeFillAllCommand(*d, 0, kPerm, 1.0, 1.0, {1, LayerPart::Mask}));
    EXPECT_EQ(d->undoName(), "Fill permeability mask");
    brush.mode = BrushMode::Paint;
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {1, LayerPart::Pixels}));
    EXPECT_EQ(d->undoName(), "Paint permeability");

    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/material/density", 640.0));
    EXPECT_EQ(d->undoName(), "Set ball density");
    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/material/shell/surface_density", 12.0));
    EXPECT_EQ(d->undoName(), "Set ball shell surface density");
    executeOrFail(
        *d, makeSetPropertyCommand(*d, "/bodies/0/position", nlohmann::json::array({0, 1, 0})));
    EXPECT_EQ(d->undoName(), "Set ball position");
    executeOrFail(*d, makeSetPropertyCommand(*d, "/bodies/0/position/1", 2.0));
    EXPECT_EQ(d->undoName(), "Set ball position y");
    EXPECT_EQ(propertyLabel(d->project(), "/medium/density"), "medium density");
    EXPECT_EQ(propertyLabel(d->project(), "/bodies/7/drag_coefficient"), "body 8 drag coefficient");
}

/// The map's integral over the body's surface, m^2: each bake entry's area times the map's
/// value at its texel (the way the physics reads a map), from a bake of the mesh at 256^2.
double surfaceIntegral(const TriangleMesh& mesh, const PaintedMap& map) {
    BakeSettings settings;
    settings.size = 256;
    Result<SurfaceTextures> baked = bakeSurfaceTextures(mesh, settings);
    EXPECT_TRUE(baked.ok());
    if (!baked) return 0;
    const std::vector<double> values = sampleAtTexels(map, *baked, 1.0);
    double sum = 0;
    for (std::size_t i = 0; i < values.size(); ++i) sum += values[i] * baked->area[i];
    return sum;
}

TEST(EditorLayers, ResizingAMapKeepsItsContentAndItsSurfaceIntegral) {
    // A 64 x 64 map with a smooth stroke and a sharp one, resized to 256 and back to 64 (and
    // to 40, which no power of two divides): the map's integral over the surface stays within
    // 0.5% each time, the content stays where it was, and each resize is one undo step that
    // gives the map before it back byte for byte. On a map with layers every layer follows.
    auto d = openOrFail(sphereProject("resize"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.1, ""));
    Brush brush;
    brush.radius = 0.3;
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke()));
    brush.radius = 0.1;
    brush.falloff = Falloff::Constant;
    brush.value = 0.8;
    executeOrFail(
        *d, makeStrokeCommand(*d, 0, kPerm, brush, std::vector<Eigen::Vector3d>{{0, 0.5, 0}}));
    const TriangleMesh& mesh = *d->assets(0).mesh;
    const PaintedMap original = *d->map(0, kPerm);
    const double integral = surfaceIntegral(mesh, original);
    ASSERT_GT(integral, 0.1 * 4 * 3.14159 * 0.25 * 0.9);

    executeOrFail(*d, makeResizeMapCommand(*d, 0, kPerm, 256, 256));
    ASSERT_EQ(d->map(0, kPerm)->width, 256);
    EXPECT_EQ(d->undoName(), "Resize permeability map to 256 x 256");
    EXPECT_NEAR(surfaceIntegral(mesh, *d->map(0, kPerm)), integral, 0.005 * integral);
    executeOrFail(*d, makeResizeMapCommand(*d, 0, kPerm, kSize, kSize));
    const PaintedMap back = *d->map(0, kPerm);
    ASSERT_EQ(back.width, kSize);
    EXPECT_NEAR(surfaceIntegral(mesh, back), integral, 0.005 * integral);
    // Up then down by the same factor: each pixel near where it was (the sharp stroke's edge
    // is softened by the linear growth, by at most a third of the step there).
    double worst = 0;
    for (std::size_t i = 0; i < back.values.size(); ++i)
        worst = std::max(worst, double(std::abs(back.values[i] - original.values[i])));
    EXPECT_LT(worst, 0.35);
    executeOrFail(*d, makeResizeMapCommand(*d, 0, kPerm, 40, 40));
    EXPECT_NEAR(surfaceIntegral(mesh, *d->map(0, kPerm)), integral, 0.005 * integral);

    // Three undos: the original, byte for byte; the redo the same sizes again.
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(d->undo());
    EXPECT_EQ(d->map(0, kPerm)->values, original.values);
    ASSERT_TRUE(d->redo());
    EXPECT_EQ(d->map(0, kPerm)->width, 256);

    // With layers: every layer at the new size, the map their flattening.
    ASSERT_TRUE(d->undo());
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "top", 1.0));
    executeOrFail(*d, makeAddMaskCommand(*d, 0, kPerm, 1, 0.5));
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke()));
    const double layered = surfaceIntegral(mesh, *d->map(0, kPerm));
    executeOrFail(*d, makeResizeMapCommand(*d, 0, kPerm, 128, 128));
    const LayerStack& stack = *d->layers(0, kPerm);
    EXPECT_EQ(stack.width, 128);
    for (const MapLayer& layer : stack.layers) {
        for (LayerPart part : {LayerPart::Pixels, LayerPart::Mask, LayerPart::Coverage}) {
            if (layer.part(part)) EXPECT_EQ(layer.part(part)->width, 128) << layer.name;
        }
    }
    EXPECT_EQ(d->map(0, kPerm)->values, flattenLayers(stack).values);
    // Each part is resampled on its own and the flattening multiplies them (value times
    // coverage times mask): the product of filtered parts is not the filtered product, here
    // 0.57% off; within 1%.
    EXPECT_NEAR(surfaceIntegral(mesh, *d->map(0, kPerm)), layered, 0.01 * layered);
}

TEST(EditorLayers, SaveAndReopenRestoreTheStackAndTheMapIsItsFlattening) {
    const fs::path project = sphereProject("save");
    auto d = openOrFail(project);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.1, ""));
    Brush brush;
    brush.radius = 0.4;
    brush.value = 0.7;
    brush.strength = 0.6;
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "stain", 1.0));
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke()));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "tint", 0.9));
    executeOrFail(*d, makeAddMaskCommand(*d, 0, kPerm, 2, 0.0));
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke(), {2, LayerPart::Mask}));
    LayerEdit edit;
    edit.blend = BlendMode::Screen;
    edit.opacity = 0.8;
    executeOrFail(*d, makeSetLayerCommand(*d, 0, kPerm, 2, edit));
    ASSERT_TRUE(d->save().ok());

    const fs::path mapFile = d->assets(0).maps[0].path;
    const fs::path sideFile = layersPathFor(mapFile);
    ASSERT_TRUE(fs::exists(sideFile));
    const std::string savedSide = test::readFile(sideFile);

    auto reopened = openOrFail(project);
    ASSERT_TRUE(reopened);
    const LayerStack* stack = reopened->layers(0, kPerm);
    ASSERT_TRUE(stack) << reopened->assets(0).maps[0].error;
    ASSERT_EQ(stack->layers.size(), 3u);
    EXPECT_EQ(stack->layers[1].name, "stain");
    EXPECT_EQ(stack->layers[2].blend, BlendMode::Screen);
    EXPECT_FLOAT_EQ(stack->layers[2].opacity, 0.8f);
    EXPECT_TRUE(stack->layers[2].mask);
    // The reopened stack is the saved one, value for value (layer pixels are kept at the
    // file's 16 bits), and writes the same bytes.
    EXPECT_TRUE(*stack == *d->layers(0, kPerm));
    EXPECT_TRUE(layerStackToJson(*stack) == savedSide);
    // The map the engine reads is the stack's flattening.
    Result<PaintedMap> onDisk = loadPaintedMap(mapFile);
    ASSERT_TRUE(onDisk.ok());
    EXPECT_EQ(encodePaintedMapPng16(*onDisk), encodePaintedMapPng16(flattenLayers(*stack)));

    // A map changed by another program no longer matches its side file: the PNG wins.
    ASSERT_TRUE(savePaintedMap(uniformMap(kSize, kSize, 0.5f), mapFile).ok());
    auto changed = openOrFail(project);
    ASSERT_TRUE(changed);
    EXPECT_FALSE(changed->layers(0, kPerm));
    EXPECT_NE(changed->assets(0).maps[0].error.find("do not flatten"), std::string::npos);
    EXPECT_NEAR(changed->map(0, kPerm)->values[0], 0.5f, 1.0 / 65535);
}

TEST(EditorLayers, AutosaveRecoversTheStack) {
    auto d = openOrFail(sphereProject("autosave"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.3, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "f", 0.6));
    ASSERT_TRUE(d->autosave().ok());
    Result<std::unique_ptr<Document>> recovered = Document::recover(d->autosavePath());
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    ASSERT_TRUE((*recovered)->layers(0, kPerm));
    EXPECT_EQ(layerStackToJson(*(*recovered)->layers(0, kPerm)),
              layerStackToJson(*d->layers(0, kPerm)));
    d->discardAutosave();
}

TEST(EditorLayers, EditScriptRunsLayerOps) {
    auto d = openOrFail(sphereProject("script"));
    ASSERT_TRUE(d);
    const nlohmann::json script = nlohmann::json::parse(R"([
        {"op": "new_map", "size": 32, "value": 0.5},
        {"op": "layer_add", "kind": "fill", "name": "dry", "value": 0.0},
        {"op": "layer_set", "layer": 1, "opacity": 0.5, "blend": "darken"},
        {"op": "layer_add", "kind": "paint", "name": "top"},
        {"op": "layer_move", "layer": 2, "to": 1},
        {"op": "mask_add", "layer": 2, "value": 1.0},
        {"op": "fill_all", "layer": 2, "mask": true, "value": 0.0, "strength": 0.5},
        {"op": "layer_set", "layer": 1, "visible": false}
    ])");
    Result<nlohmann::json> ran = runEditScript(*d, script);
    ASSERT_TRUE(ran.ok()) << ran.error().message;
    const LayerStack* stack = d->layers(0, kPerm);
    ASSERT_TRUE(stack);
    ASSERT_EQ(stack->layers.size(), 3u);
    EXPECT_EQ(stack->layers[1].name, "top");
    EXPECT_FALSE(stack->layers[1].visible);
    EXPECT_EQ(stack->layers[2].name, "dry");
    EXPECT_EQ(stack->layers[2].blend, BlendMode::Darken);
    // 0.5, then darken toward 0 at opacity 0.5 x mask 0.5: 0.5 - 0.5 * 0.25 = 0.375 (with the
    // base and the mask at 16 bits).
    const float base = quantize16(0.5f), alpha = 0.5f * quantize16(0.5f);
    for (float v : d->map(0, kPerm)->values) ASSERT_NEAR(v, base - base * alpha, 1e-6);

    const nlohmann::json bad = nlohmann::json::parse(R"([{"op": "layer_remove", "layer": 7}])");
    Result<nlohmann::json> refused = runEditScript(*d, bad);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("no layer 7"), std::string::npos)
        << refused.error().message;
}

TEST(EditorLayers, RenameIsOneStepUndoneByteForByteAndKeptBySaving) {
    const fs::path project = sphereProject("rename");
    auto d = openOrFail(project);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.25, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "", 1.0));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "", 1.0));
    ASSERT_EQ(d->layers(0, kPerm)->layers[2].name, "Layer 2");
    const std::string before = layerStackToJson(*d->layers(0, kPerm));
    const std::size_t steps = d->historyPosition();

    // Spaces typed at the ends are not part of the name.
    executeOrFail(*d, makeRenameLayerCommand(*d, 0, kPerm, 2, "  Rust "));
    EXPECT_EQ(d->historyPosition(), steps + 1);
    EXPECT_EQ(d->undoName(), "Rename layer 'Layer 2' to 'Rust'");
    const std::string after = layerStackToJson(*d->layers(0, kPerm));
    EXPECT_EQ(d->layers(0, kPerm)->layers[2].name, "Rust");
    EXPECT_NE(after.find("\"name\": \"Rust\""), std::string::npos);

    ASSERT_TRUE(d->undo());
    EXPECT_TRUE(layerStackToJson(*d->layers(0, kPerm)) == before);
    ASSERT_TRUE(d->redo());
    EXPECT_TRUE(layerStackToJson(*d->layers(0, kPerm)) == after);

    ASSERT_TRUE(d->save().ok());
    const fs::path sideFile = layersPathFor(d->assets(0).maps[0].path);
    EXPECT_TRUE(test::readFile(sideFile) == after);
    auto reopened = openOrFail(project);
    ASSERT_TRUE(reopened);
    const LayerStack* stack = reopened->layers(0, kPerm);
    ASSERT_TRUE(stack) << reopened->assets(0).maps[0].error;
    ASSERT_EQ(stack->layers.size(), 3u);
    EXPECT_EQ(stack->layers[2].name, "Rust");
    EXPECT_EQ(stack->layers[1].name, "Layer 1");
}

TEST(EditorLayers, RenameRefusesEmptyDuplicateAndUnchangedNamesWithoutAStep) {
    auto d = openOrFail(sphereProject("rename_refused"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.25, ""));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "Rust", 1.0));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "Wet", 0.5));
    const std::string stack = layerStackToJson(*d->layers(0, kPerm));
    const std::size_t steps = d->historyPosition();
    auto refused = [&](int layer, std::string_view name, const std::string& why) {
        Result<std::unique_ptr<Command>> c = makeRenameLayerCommand(*d, 0, kPerm, layer, name);
        ASSERT_FALSE(c.ok()) << "'" << name << "' was taken";
        EXPECT_NE(c.error().message.find(why), std::string::npos) << c.error().message;
    };
    refused(1, "", "needs a name");
    refused(1, " \t ", "needs a name");
    refused(2, "Rust", "already has a layer named 'Rust'");
    refused(2, " Base", "already has a layer named 'Base'");
    refused(1, "Rust", "named 'Rust' already");
    refused(1, "two\nlines", "one line");
    refused(9, "Nine", "no layer 9");
    // The same checks hold for the other ways a name comes in.
    LayerEdit edit;
    edit.name = "Wet";
    EXPECT_FALSE(makeSetLayerCommand(*d, 0, kPerm, 1, edit).ok());
    edit.opacity = 0.5;
    EXPECT_FALSE(makeSetLayerCommand(*d, 0, kPerm, 1, edit).ok()) << "a name with other settings";
    EXPECT_FALSE(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "Rust", 1.0).ok());
    EXPECT_EQ(d->historyPosition(), steps);
    EXPECT_TRUE(layerStackToJson(*d->layers(0, kPerm)) == stack);

    // A name change through the settings edit reads as a rename in the history too.
    LayerEdit rename;
    rename.name = "Rust 2";
    executeOrFail(*d, makeSetLayerCommand(*d, 0, kPerm, 2, rename));
    EXPECT_EQ(d->undoName(), "Rename layer 'Wet' to 'Rust 2'");
    // Default names count from the stack's size and skip the ones taken (a fourth layer
    // would be "Layer 4", which a renamed layer already is).
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "", 1.0));
    EXPECT_EQ(d->layers(0, kPerm)->layers[3].name, "Layer 3");
    executeOrFail(*d, makeRenameLayerCommand(*d, 0, kPerm, 3, "Layer 4"));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Paint, "", 1.0));
    const LayerStack* layers = d->layers(0, kPerm);
    ASSERT_EQ(layers->layers.size(), 5u);
    EXPECT_EQ(layers->layers[4].name, "Layer 5");
    for (std::size_t i = 0; i < layers->layers.size(); ++i) {
        for (std::size_t k = i + 1; k < layers->layers.size(); ++k)
            EXPECT_NE(layers->layers[i].name, layers->layers[k].name);
    }
}

TEST(EditorLayers, EditScriptRenamesALayer) {
    auto d = openOrFail(sphereProject("script_rename"));
    ASSERT_TRUE(d);
    const nlohmann::json script = nlohmann::json::parse(R"([
        {"op": "new_map", "size": 32, "value": 0.5},
        {"op": "layer_add", "kind": "paint"},
        {"op": "layer_rename", "layer": 1, "name": "Rust"},
        {"op": "layer_rename", "layer": 0, "name": "Hull"},
        {"op": "undo"}
    ])");
    Result<nlohmann::json> ran = runEditScript(*d, script);
    ASSERT_TRUE(ran.ok()) << ran.error().message;
    EXPECT_EQ((*ran)[2]["name"], "Rename layer 'Layer 1' to 'Rust'");
    EXPECT_EQ((*ran)[3]["name"], "Rename layer 'Base' to 'Hull'");
    const LayerStack* stack = d->layers(0, kPerm);
    ASSERT_TRUE(stack);
    EXPECT_EQ(stack->layers[0].name, "Base");
    EXPECT_EQ(stack->layers[1].name, "Rust");

    Result<nlohmann::json> duplicate = runEditScript(
        *d, nlohmann::json::parse(R"([{"op": "layer_rename", "layer": 0, "name": "Rust"}])"));
    ASSERT_FALSE(duplicate.ok());
    EXPECT_NE(duplicate.error().message.find("command 0"), std::string::npos)
        << duplicate.error().message;
    EXPECT_NE(duplicate.error().message.find("already has a layer named 'Rust'"), std::string::npos)
        << duplicate.error().message;
    Result<nlohmann::json> unnamed =
        runEditScript(*d, nlohmann::json::parse(R"([{"op": "layer_rename", "layer": 0}])"));
    EXPECT_FALSE(unnamed.ok());
}

TEST(EditorLayers, NewMapOverSavedPaintIsUndoneToTheSavedMap) {
    // The data loss of the window's "New map": replacing a saved map, then undo, lost it, and
    // the next save wrote a blank map.
    const fs::path project = sphereProject("newmap");
    const fs::path mapFile = project.parent_path() / "saved.png";
    PaintedMap saved = uniformMap(kSize, kSize, 0.0f);
    for (std::size_t i = 0; i < saved.values.size(); ++i) saved.values[i] = float(i % 7) / 6.0f;
    ASSERT_TRUE(savePaintedMap(saved, mapFile).ok());
    {
        auto d = openOrFail(project);
        ASSERT_TRUE(d);
        Result<std::unique_ptr<Command>> set =
            makeSetPropertyCommand(*d, "/bodies/0/permeability_map", "saved.png");
        executeOrFail(*d, std::move(set));
        ASSERT_TRUE(d->save().ok());
    }
    const std::string savedBytes = test::readFile(mapFile);
    auto d = openOrFail(project);
    ASSERT_TRUE(d);
    ASSERT_TRUE(d->map(0, kPerm));
    const std::string before = snapshot(*d);

    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.0, "saved.png"));
    EXPECT_EQ(d->map(0, kPerm)->values[1], 0.0f);
    ASSERT_TRUE(d->undo());
    ASSERT_TRUE(d->map(0, kPerm)) << "the undo of New map gives the saved map back";
    EXPECT_TRUE(snapshot(*d) == before);
    EXPECT_FALSE(d->dirty());
    ASSERT_TRUE(d->redo());
    ASSERT_TRUE(d->undo());
    EXPECT_TRUE(snapshot(*d) == before);

    // A stroke now paints over the saved pixels, and saving keeps them.
    Brush brush;
    brush.radius = 0.2;
    brush.falloff = Falloff::Constant;
    executeOrFail(*d, makeStrokeCommand(*d, 0, kPerm, brush, poleStroke()));
    ASSERT_TRUE(d->save().ok());
    Result<PaintedMap> written = loadPaintedMap(mapFile);
    ASSERT_TRUE(written.ok());
    std::size_t kept = 0;
    for (std::size_t i = 0; i < saved.values.size(); ++i) {
        if (written->values[i] != 1.0f) {
            ASSERT_NEAR(written->values[i], saved.values[i], 1.0 / 65535) << "pixel " << i;
            ++kept;
        }
    }
    EXPECT_GT(kept, saved.values.size() / 2);
    EXPECT_TRUE(test::readFile(mapFile) != savedBytes);  // the stroke is in it too
}

TEST(EditorLayers, FillsMoveByStrengthAndSayWhenTheMeshIsOneIsland) {
    auto d = openOrFail(sphereProject("fill"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.2, ""));
    executeOrFail(*d, makeFillAllCommand(*d, 0, kPerm, 1.0, 0.25));  // 0.2 + (1 - 0.2) / 4
    for (float v : d->map(0, kPerm)->values) ASSERT_FLOAT_EQ(v, 0.4f);
    // The unit sphere's UVs are one island: fill island covers every pixel with a sample, and
    // its name says why.
    Result<std::unique_ptr<Command>> island =
        makeFillIslandCommand(*d, 0, kPerm, {0.5, 0, 0}, 0.0, false, 1.0);
    ASSERT_TRUE(island.ok()) << island.error().message;
    EXPECT_NE((*island)->name().find("one UV island"), std::string::npos) << (*island)->name();
}

/// Layers cost memory per image: the count, the samples of all layer images, and the side
/// file's size are limited before anything is allocated, with an error naming the file.
TEST(EditorLayers, LayerCountAndSizeAreRefusedBeforeAllocating) {
    // A side file declaring 65 fill layers: refused by count.
    std::string many = R"({"plimsoll_map_layers": 1, "width": 4, "height": 4, "layers": [)";
    for (int i = 0; i < 65; ++i)
        many += std::string(i ? "," : "") + R"({"kind": "fill", "value": 0.5})";
    many += "]}";
    Result<LayerStack> parsed = parseLayerStack(many, "map.layers.json");
    ASSERT_FALSE(parsed.ok());
    EXPECT_NE(parsed.error().message.find(
                  "map.layers.json: 65 layers, more than the limit kMaxMapLayers"),
              std::string::npos)
        << parsed.error().message;
    // A 4096^2 map declaring nine paint layers (pixels and coverage each): 18 images of 16.7M
    // samples, more than kMaxLayerSamples, refused before a single image is decoded (the
    // images here are not even valid PNGs).
    std::string big = R"({"plimsoll_map_layers": 1, "width": 4096, "height": 4096, "layers": [)";
    for (int i = 0; i < 9; ++i)
        big += std::string(i ? "," : "") +
               R"({"pixels_png_base64": "AAAA", "coverage_png_base64": "AAAA"})";
    big += "]}";
    parsed = parseLayerStack(big, "big.layers.json");
    ASSERT_FALSE(parsed.ok());
    EXPECT_NE(parsed.error().message.find("big.layers.json: 18 layer images of 4096 x 4096"),
              std::string::npos)
        << parsed.error().message;
    EXPECT_EQ(parsed.error().kind, ErrorKind::limit);
    // Adding layers: the budget of a 4096^2 stack with seven paint layers holds one more, not two.
    LayerStack stack;
    stack.width = stack.height = 4096;
    for (int i = 0; i < 7; ++i) {
        MapLayer l;
        l.pixels = std::make_shared<PaintedMap>();
        l.coverage = std::make_shared<PaintedMap>();
        stack.layers.push_back(l);
    }
    EXPECT_TRUE(checkLayerBudget(stack, 1, 2).ok());
    const Status two = checkLayerBudget(stack, 2, 4);
    ASSERT_FALSE(two.ok());
    EXPECT_NE(two.error().message.find("kMaxLayerSamples"), std::string::npos)
        << two.error().message;
    EXPECT_TRUE(checkLayerBudget(stack, 56, 0).ok());  // fill layers cost no images: 63 layers
    EXPECT_FALSE(checkLayerBudget(stack, 58, 0).ok());
}

// --- folders --------------------------------------------------------------------------------

/// Two pixels: a Base [0.5, 0.5], then folder "group" over a paint layer A of 0.8 with coverage
/// [1, 0.5] and a fill B of 0.4 at opacity 0.5 in multiply.
LayerStack folderStack(BlendMode folderBlend, float folderOpacity) {
    LayerStack stack;
    stack.width = 2;
    stack.height = 1;
    MapLayer base;
    base.name = "Base";
    base.pixels = std::make_shared<PaintedMap>(uniformMap(2, 1, 0.5f));
    MapLayer a;
    a.name = "A";
    a.pixels = std::make_shared<PaintedMap>(uniformMap(2, 1, 0.8f));
    a.coverage = std::make_shared<PaintedMap>(uniformMap(2, 1, 1.0f));
    a.coverage->values = {1.0f, 0.5f};
    a.inFolder = true;
    MapLayer b;
    b.name = "B";
    b.kind = LayerKind::Fill;
    b.fillValue = 0.4f;
    b.opacity = 0.5f;
    b.blend = BlendMode::Multiply;
    b.inFolder = true;
    MapLayer folder;
    folder.name = "group";
    folder.kind = LayerKind::Folder;
    folder.blend = folderBlend;
    folder.opacity = folderOpacity;
    stack.layers = {base, a, b, folder};
    return stack;
}

TEST(EditorLayers, FolderFlattensAsItsLayersCompositedThenBlendedAsOne) {
    // The group alone, by hand (a over a backdrop of alpha ab: source (1 - ab) v + ab blend,
    // alpha a + ab (1 - a), value (a source + ab c (1 - a)) / alpha).
    // Pixel 0: A covers it (0.8, alpha 1); B multiplies half way: 0.5 * 0.32 + 0.5 * 0.8 = 0.56.
    // Pixel 1: A at alpha 0.5 (0.8); B: source 0.5 * 0.4 + 0.5 * 0.32 = 0.36, alpha 0.75,
    // value (0.5 * 0.36 + 0.5 * 0.8 * 0.5) / 0.75 = 0.38 / 0.75.
    const float group0 = 0.56f, group1 = 0.38f / 0.75f, alpha1 = 0.75f;
    LayerStack normal = folderStack(BlendMode::Normal, 0.5f);
    ASSERT_TRUE(checkStack(normal).ok());
    PaintedMap flat = flattenLayers(normal);
    EXPECT_NEAR(flat.values[0], 0.5f + (group0 - 0.5f) * 0.5f, 1e-6);           // 0.53
    EXPECT_NEAR(flat.values[1], 0.5f + (group1 - 0.5f) * 0.5f * alpha1, 1e-6);  // 0.5025
    // Not each layer at half its opacity: that gives 0.65, then 0.5525 at pixel 0.
    EXPECT_GT(std::abs(flat.values[0] - 0.5525f), 0.02f);

    LayerStack multiply = folderStack(BlendMode::Multiply, 1.0f);
    flat = flattenLayers(multiply);
    EXPECT_NEAR(flat.values[0], 0.5f * group0, 1e-6);                           // 0.28
    EXPECT_NEAR(flat.values[1], 0.5f + (0.5f * group1 - 0.5f) * alpha1, 1e-6);  // 0.315

    // A hidden folder hides its layers; a layer hidden inside counts for nothing.
    LayerStack hidden = folderStack(BlendMode::Normal, 1.0f);
    hidden.layers[3].visible = false;
    flat = flattenLayers(hidden);
    EXPECT_FLOAT_EQ(flat.values[0], 0.5f);
    EXPECT_FLOAT_EQ(flat.values[1], 0.5f);
    LayerStack inner = folderStack(BlendMode::Normal, 1.0f);
    inner.layers[2].visible = false;
    flat = flattenLayers(inner);
    EXPECT_NEAR(flat.values[0], 0.8f, 1e-6);
    EXPECT_NEAR(flat.values[1], 0.5f + (0.8f - 0.5f) * 0.5f, 1e-6);

    // A folder's layer needs its folder right above it.
    LayerStack stray = folderStack(BlendMode::Normal, 1.0f);
    stray.layers.pop_back();
    EXPECT_FALSE(checkStack(stray).ok());
}

TEST(EditorLayers, FolderOperationsUndoAndRedoByteForByte) {
    auto d = openOrFail(sphereProject("folders_undo"));
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.25, ""));
    UndoTrail trail(*d);
    const auto step = [&](Result<std::unique_ptr<Command>> command) {
        trail.step(std::move(command));
    };
    step(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "wet", 0.75));  // 1
    step(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Folder, "", 1.0));    // 2
    EXPECT_EQ(d->undoName(), "Add folder");
    EXPECT_EQ(d->layers(0, kPerm)->layers[2].name, "Folder 2");
    step(makeMoveIntoFolderCommand(*d, 0, kPerm, 1, 2));  // wet 0 -> in, folder at 2
    ASSERT_EQ(folderOf(*d->layers(0, kPerm), 1), 2);
    step(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "dry", 0.0, 2));  // under the entry
    EXPECT_TRUE(d->layers(0, kPerm)->layers[2].inFolder) << "added right below the entry";
    LayerEdit edit;
    edit.opacity = 0.5;
    edit.blend = BlendMode::Screen;
    step(makeSetLayerCommand(*d, 0, kPerm, 3, edit));
    step(makeMoveLayerCommand(*d, 0, kPerm, 3, 0));  // the folder and its two layers to the bottom
    const LayerStack& moved = *d->layers(0, kPerm);
    ASSERT_EQ(moved.layers.size(), 4u);
    EXPECT_EQ(moved.layers[0].name, "wet");
    EXPECT_EQ(moved.layers[1].name, "dry");
    EXPECT_EQ(moved.layers[2].name, "Folder 2");
    EXPECT_EQ(moved.layers[3].name, "Base");
    step(makeMoveOutOfFolderCommand(*d, 0, kPerm, 0));  // wet leaves, above the folder
    EXPECT_EQ(d->layers(0, kPerm)->layers[2].name, "wet");
    EXPECT_EQ(folderOf(*d->layers(0, kPerm), 2), -1);
    step(makeRemoveLayerCommand(*d, 0, kPerm, 1));  // the folder, with "dry"
    EXPECT_EQ(d->undoName(), "Remove folder");
    ASSERT_EQ(d->layers(0, kPerm)->layers.size(), 2u);
    EXPECT_FALSE(d->layers(0, kPerm)->hasFolders());

    trail.undoAll();
    trail.redoAll();
    // Folders do not nest, and a layer moves among the items of its own folder.
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Folder, "outer", 1.0));
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Folder, "inner", 1.0));
    const int outer = 2, inner = 3;
    EXPECT_FALSE(makeMoveIntoFolderCommand(*d, 0, kPerm, inner, outer).ok());
    executeOrFail(*d, makeMoveIntoFolderCommand(*d, 0, kPerm, 0, outer));  // wet in "outer"
    EXPECT_FALSE(makeMoveLayerCommand(*d, 0, kPerm, 1, inner).ok());
    EXPECT_FALSE(makeAddLayerCommand(*d, 0, kPerm, LayerKind::Folder, "x", 1.0, 2).ok());
}

TEST(EditorLayers, FoldersSaveAndReopenAndOldSideFilesStillLoad) {
    const fs::path project = sphereProject("folders_save");
    auto d = openOrFail(project);
    ASSERT_TRUE(d);
    executeOrFail(*d, makeNewMapCommand(*d, 0, kPerm, kSize, kSize, 0.1, ""));
    // A layer stack without folders is written as version 1, which older editors read.
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Fill, "tint", 0.9));
    EXPECT_EQ(nlohmann::json::parse(layerStackToJson(*d->layers(0, kPerm)))["plimsoll_map_layers"],
              1);
    executeOrFail(*d, makeAddLayerCommand(*d, 0, kPerm, LayerKind::Folder, "rust", 1.0));
    executeOrFail(*d, makeMoveIntoFolderCommand(*d, 0, kPerm, 1, 2));
    LayerEdit edit;
    edit.opacity = 0.4;
    edit.blend = BlendMode::Multiply;
    edit.visible = true;
    executeOrFail(*d, makeSetLayerCommand(*d, 0, kPerm, 2, edit));
    executeOrFail(*d, makeAddMaskCommand(*d, 0, kPerm, 2, 0.5));
    ASSERT_TRUE(d->save().ok());
    const fs::path mapFile = d->assets(0).maps[0].path;
    const std::string side = test::readFile(layersPathFor(mapFile));
    EXPECT_EQ(nlohmann::json::parse(side)["plimsoll_map_layers"], 2);

    auto reopened = openOrFail(project);
    ASSERT_TRUE(reopened);
    const LayerStack* stack = reopened->layers(0, kPerm);
    ASSERT_TRUE(stack) << reopened->assets(0).maps[0].error;
    EXPECT_TRUE(*stack == *d->layers(0, kPerm));
    ASSERT_EQ(stack->layers.size(), 3u);
    EXPECT_TRUE(stack->layers[1].inFolder);
    EXPECT_EQ(stack->layers[2].kind, LayerKind::Folder);
    EXPECT_FLOAT_EQ(stack->layers[2].opacity, 0.4f);
    EXPECT_TRUE(stack->layers[2].mask);
    EXPECT_EQ(layerStackToJson(*stack), side);
    // Base 0.1 (at 16 bits), the folder's tint 0.9 multiplied at 0.4 x mask 0.5.
    const float base = quantize16(0.1f), a = 0.4f * quantize16(0.5f);
    Result<PaintedMap> onDisk = loadPaintedMap(mapFile);
    ASSERT_TRUE(onDisk.ok());
    EXPECT_NEAR(onDisk->values[0], base + (base * 0.9f - base) * a, 1.0 / 65535);

    // A version 1 file (before folders) loads as it did.
    const std::string png = base64Encode(encodePaintedMapPng16(uniformMap(2, 1, 0.5f)));
    Result<LayerStack> old = parseLayerStack(
        R"({"plimsoll_map_layers": 1, "width": 2, "height": 1, "layers": [)"
        R"({"name": "Base", "kind": "paint", "pixels_png_base64": ")" +
            png + R"("}, {"name": "f", "kind": "fill", "value": 0.25, "blend": "add"}]})",
        "old.layers.json");
    ASSERT_TRUE(old.ok()) << old.error().message;
    ASSERT_EQ(old->layers.size(), 2u);
    EXPECT_FALSE(old->hasFolders());
    EXPECT_NEAR(flattenLayers(*old).values[1], quantize16(0.5f) + 0.25f, 1e-6);
    // A folder inside a folder is refused with its name.
    Result<LayerStack> nested = parseLayerStack(
        R"({"plimsoll_map_layers": 2, "width": 2, "height": 1, "layers": [)"
        R"({"name": "Base", "pixels_png_base64": ")" +
            png +
            R"("}, {"name": "a", "kind": "folder", "layers": [{"name": "b", "kind": "folder"}]}]})",
        "nested.layers.json");
    ASSERT_FALSE(nested.ok());
    EXPECT_NE(nested.error().message.find("folder 'b' is in a folder"), std::string::npos)
        << nested.error().message;
}

TEST(EditorLayers, EditScriptRunsFolderOps) {
    auto d = openOrFail(sphereProject("folders_script"));
    ASSERT_TRUE(d);
    const nlohmann::json script = nlohmann::json::parse(R"([
        {"op": "new_map", "size": 16, "value": 0.5},
        {"op": "layer_add", "kind": "fill", "name": "one", "value": 1.0},
        {"op": "layer_add", "kind": "fill", "name": "zero", "value": 0.0},
        {"op": "layer_add", "kind": "folder", "name": "group"},
        {"op": "layer_into_folder", "layer": 1, "folder": 3},
        {"op": "layer_into_folder", "layer": 1, "folder": 3},
        {"op": "layer_set", "layer": 3, "opacity": 0.5},
        {"op": "layer_out_of_folder", "layer": 2}
    ])");
    Result<nlohmann::json> ran = runEditScript(*d, script);
    ASSERT_TRUE(ran.ok()) << ran.error().message;
    const LayerStack* stack = d->layers(0, kPerm);
    ASSERT_TRUE(stack);
    // Base, group{one}, zero: "zero" left the folder, above it, and covers everything.
    ASSERT_EQ(stack->layers.size(), 4u);
    EXPECT_EQ(stack->layers[1].name, "one");
    EXPECT_TRUE(stack->layers[1].inFolder);
    EXPECT_EQ(stack->layers[2].name, "group");
    EXPECT_EQ(stack->layers[3].name, "zero");
    for (float v : d->map(0, kPerm)->values) ASSERT_FLOAT_EQ(v, 0.0f);
    const nlohmann::json hide = nlohmann::json::parse(R"([
        {"op": "layer_remove", "layer": 3}
    ])");
    ASSERT_TRUE(runEditScript(*d, hide).ok());
    // 0.5 under the folder's "one" at 0.5: 0.75.
    for (float v : d->map(0, kPerm)->values) ASSERT_NEAR(v, quantize16(0.5f) * 0.5f + 0.5f, 1e-6);
    const nlohmann::json drop = nlohmann::json::parse(R"([{"op": "layer_remove", "layer": 2}])");
    ASSERT_TRUE(runEditScript(*d, drop).ok());
    ASSERT_EQ(d->layers(0, kPerm)->layers.size(), 1u) << "the folder went with its layer";
}

}  // namespace
}  // namespace test_editor_layers
}  // namespace plimsoll::editor
