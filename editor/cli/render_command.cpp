// `plimsoll render PROJECT --out shot.png [--view front|side|top|persp] [--overlay MAP]
// [--size WxH] [--graph]`: the viewport's image with no display, through EGL (Mesa's surfaceless
// llvmpipe on a machine without a GPU). For thumbnails and tests.
#include "cli/commands.h"

#include "cli/common.h"

#include "document/document.h"
#include "document/overlay.h"
#include "view/camera.h"
#include "render/graph_draw.h"
#include "render/headless_context.h"
#include "render/renderer.h"
#include "render/scene.h"

#include "plimsoll/io/file_util.h"

#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <memory>

namespace plimsoll::cli {

namespace {

struct RenderOptions {
    std::string project;
    std::string out;
    std::string view = "persp";
    std::string overlay = "none";
    std::string size = "800x600";
    double time = 0.0;
    bool noWater = false;
    bool noGrid = false;
    bool graph = false;
};

int runRender(const RenderOptions& o) {
    using namespace plimsoll::editor;
    int width = 0, height = 0;
    char x = 0;
    if (std::sscanf(o.size.c_str(), "%d%c%d", &width, &x, &height) != 3 || x != 'x' || width < 1 ||
        height < 1 || width > 16384 || height > 16384) {
        std::cerr << "error: --size: expected WxH (1..16384), got " << o.size << "\n";
        return kExitUsage;
    }
    const std::optional<ViewPreset> view = parseViewPreset(o.view);
    const std::optional<Overlay> overlay = parseOverlay(o.overlay);
    if (!view || !overlay) {
        std::cerr << "error: unknown " << (!view ? "--view " + o.view : "--overlay " + o.overlay)
                  << "\n";
        return kExitUsage;
    }
    Result<std::unique_ptr<Document>> document = Document::open(o.project);
    if (!document) {
        std::cerr << "error: " << document.error().message << "\n";
        return kExitFailure;
    }
    for (std::size_t b = 0; b < (*document)->bodyCount(); ++b) {
        if (!(*document)->assets(b).mesh) {
            std::cerr << "warning: body " << b << ": " << (*document)->assets(b).meshError << "\n";
        }
    }
    const auto start = std::chrono::steady_clock::now();
    Result<std::unique_ptr<HeadlessContext>> context = HeadlessContext::create();
    if (!context) {
        std::cerr << "error: " << context.error().message << "\n";
        return kExitFailure;
    }
    Result<std::unique_ptr<Renderer>> renderer = Renderer::create();
    if (!renderer) {
        std::cerr << "error: " << renderer.error().message << "\n";
        return kExitFailure;
    }
    Result<std::unique_ptr<OffscreenTarget>> target = OffscreenTarget::create(width, height);
    if (!target) {
        std::cerr << "error: " << target.error().message << "\n";
        return kExitFailure;
    }
    const auto ready = std::chrono::steady_clock::now();
    RenderScene scene = buildRenderScene(**document, **renderer, *overlay);
    if (o.noWater) scene.water = nullptr;
    scene.grid = scene.axes = !o.noGrid;
    scene.time = o.time;
    const Camera camera = Camera::preset(*view, (*document)->worldBounds());
    // --graph: each body's water graph inside its hull, the hull see-through.
    std::unique_ptr<GraphDrawer> graphDrawer;
    std::vector<RenderGraph> graphs;
    if (o.graph) {
        Result<std::unique_ptr<GraphDrawer>> made = GraphDrawer::create();
        if (!made) {
            std::cerr << "error: " << made.error().message << "\n";
            return kExitFailure;
        }
        graphDrawer = std::move(made).value();
        for (std::size_t b = 0; b < (*document)->bodyCount(); ++b) {
            if (const WaterGraph* graph = (*document)->graph(b)) {
                graphs.push_back(RenderGraph{graph, (*document)->bodyPose(b), {}, -1, {}});
                scene.bodies[b].alpha = 0.3f;
            }
        }
        scene.drawInside = [&](const Eigen::Matrix4f& viewProj) {
            for (const RenderGraph& g : graphs) graphDrawer->draw(g, viewProj, camera);
        };
    }
    (*target)->bind();
    (*renderer)->draw(scene, camera, width, height);
    const std::vector<std::uint8_t> pixels = (*target)->readRgba();
    const auto drawn = std::chrono::steady_clock::now();
    std::string png;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 4, pixels.data(), width * 4)) {
        std::cerr << "error: PNG encoding failed\n";
        return kExitFailure;
    }
    Status written = writeFileAtomically(o.out, [&](std::ostream& out) {
        out.write(png.data(), static_cast<std::streamsize>(png.size()));
        return static_cast<bool>(out);
    });
    if (!written) {
        std::cerr << "error: " << written.error().message << "\n";
        return kExitFailure;
    }
    using ms = std::chrono::duration<double, std::milli>;
    nlohmann::json report;
    report["out"] = o.out;
    report["width"] = width;
    report["height"] = height;
    report["view"] = o.view;
    report["overlay"] = o.overlay;
    report["context"] = (*context)->description();
    report["setup_ms"] = ms(ready - start).count();
    report["draw_ms"] = ms(drawn - ready).count();
    std::cout << reportJson(report) << "\n";
    return kExitOk;
}

}  // namespace

void addRenderCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = root.add_subcommand(
        "render", "Draw the viewport's image of a project to a PNG, with no display (EGL)");
    cmd->add_option("project", o->project, "Project file (*.plim.json)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--out", o->out, "PNG file to write")->required()->check(kNonEmptyPath);
    cmd->add_option("--view", o->view, "front, side, top (orthographic) or persp")
        ->check(CLI::IsMember({"front", "side", "top", "persp"}))
        ->capture_default_str();
    cmd->add_option("--overlay", o->overlay,
                    "Map over the mesh: none, permeability, density, thickness, coverage, "
                    "position (PT), area (AVT)")
        ->check(CLI::IsMember(
            {"none", "permeability", "density", "thickness", "coverage", "position", "area"}))
        ->capture_default_str();
    cmd->add_option("--size", o->size, "Image size WxH in pixels")->capture_default_str();
    cmd->add_option("--time", o->time, "Time of the waves, s")->capture_default_str();
    cmd->add_flag("--no-water", o->noWater, "Leave out the water surface");
    cmd->add_flag("--no-grid", o->noGrid, "Leave out the grid and axes");
    cmd->add_flag("--graph", o->graph,
                  "Draw each body's water graph (nodes filled to their water, pipes) inside its "
                  "hull, drawn see-through");
    cmd->callback([o, &selected] { selected = [o] { return runRender(*o); }; });
}

}  // namespace plimsoll::cli
