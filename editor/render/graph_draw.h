// Drawing a water graph in the 3D view (OpenGL 4.5 core, like renderer.h): sphere nodes at
// their capacity's radius (graph_pick.h), box nodes as their boxes, each filled to its water
// level (the part below the level darker and bluer), pipes as cylinders of their radius
// (closed pipes dark red and thinner), selected nodes and pipes brighter. The renderer calls
// it between the opaque and the see-through bodies (RenderScene::drawInside), so the hull
// around the graph is drawn over it with alpha.
#pragma once

#include "view/camera.h"

#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/core/result.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace plimsoll::editor {

struct RenderGraph {
    const WaterGraph* graph = nullptr;
    Pose pose;                        ///< of the body, object -> world
    std::vector<bool> selectedNodes;  ///< per node (shorter: unselected)
    int selectedPipe = -1;
    /// Water per node to draw (a running simulation's); empty: the graph's own.
    std::vector<double> water;
};

class GraphDrawer {
public:
    /// Compiles the shader and builds the unit shapes; needs a current OpenGL 4.5 context.
    static Result<std::unique_ptr<GraphDrawer>> create();
    ~GraphDrawer();
    GraphDrawer(const GraphDrawer&) = delete;
    GraphDrawer& operator=(const GraphDrawer&) = delete;

    /// Draws into the bound framebuffer with the current viewport, depth tested.
    void draw(const RenderGraph& graph, const Eigen::Matrix4f& viewProj, const Camera& camera);

private:
    GraphDrawer() = default;
    struct Shape {
        unsigned vao = 0, vbo = 0;
        int count = 0;
    };
    void drawShape(const Shape& shape, const Eigen::Matrix4f& model, const Eigen::Vector3f& colour,
                   const Eigen::Vector3f& waterColour, float level);
    unsigned program_ = 0;
    Shape sphere_, cylinder_, cube_;
};

}  // namespace plimsoll::editor
