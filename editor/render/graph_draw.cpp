#include "render/graph_draw.h"

#include "document/graph_view.h"
#include "render/gl_program.h"
#include "view/graph_pick.h"
#include "render/shaders.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>

namespace plimsoll::editor {

namespace {

/// Triangles of (position, normal) floats.
using Vertices = std::vector<float>;

void vertex(Vertices& v, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
    v.insert(v.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
}

Vertices unitSphere(int slices, int stacks) {
    Vertices v;
    auto at = [](double theta, double phi) {
        return Eigen::Vector3f(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                               float(std::sin(theta) * std::sin(phi)));
    };
    for (int i = 0; i < stacks; ++i) {
        const double t0 = std::numbers::pi * i / stacks, t1 = std::numbers::pi * (i + 1) / stacks;
        for (int j = 0; j < slices; ++j) {
            const double p0 = 2 * std::numbers::pi * j / slices,
                         p1 = 2 * std::numbers::pi * (j + 1) / slices;
            const Eigen::Vector3f a = at(t0, p0), b = at(t1, p0), c = at(t1, p1), d = at(t0, p1);
            for (const Eigen::Vector3f& p : {a, b, c, a, c, d}) vertex(v, p, p);
        }
    }
    return v;
}

/// Radius 1, from z = 0 to z = 1.
Vertices unitCylinder(int slices) {
    Vertices v;
    for (int j = 0; j < slices; ++j) {
        const double p0 = 2 * std::numbers::pi * j / slices,
                     p1 = 2 * std::numbers::pi * (j + 1) / slices;
        const Eigen::Vector3f n0(float(std::cos(p0)), float(std::sin(p0)), 0);
        const Eigen::Vector3f n1(float(std::cos(p1)), float(std::sin(p1)), 0);
        const Eigen::Vector3f z(0, 0, 1);
        vertex(v, n0, n0), vertex(v, n1, n1), vertex(v, n1 + z, n1);
        vertex(v, n0, n0), vertex(v, n1 + z, n1), vertex(v, n0 + z, n0);
    }
    return v;
}

/// Edge 1, centred at the origin.
Vertices unitCube() {
    Vertices v;
    for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {-1.0f, 1.0f}) {
            Eigen::Vector3f n = Eigen::Vector3f::Zero();
            n[axis] = sign;
            const Eigen::Vector3f u = Eigen::Vector3f::Unit((axis + 1) % 3) * 0.5f;
            const Eigen::Vector3f w = Eigen::Vector3f::Unit((axis + 2) % 3) * 0.5f;
            const Eigen::Vector3f c = n * 0.5f;
            const Eigen::Vector3f a = c - u - w, b = c + u - w, d = c + u + w, e = c - u + w;
            for (const Eigen::Vector3f& p : {a, b, d, a, d, e}) vertex(v, p, n);
        }
    }
    return v;
}

Eigen::Matrix4f affine(const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation) {
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<3, 3>(0, 0) = linear.cast<float>();
    m.block<3, 1>(0, 3) = translation.cast<float>();
    return m;
}

}  // namespace

Result<std::unique_ptr<GraphDrawer>> GraphDrawer::create() {
    std::unique_ptr<GraphDrawer> d(new GraphDrawer());
    Result<unsigned> program = linkGlProgram({shaders::graph_node_vert, shaders::water_view_vert},
                                             {shaders::graph_node_frag, shaders::water_view_frag});
    if (!program) return withContext("graph ", program.error());
    d->program_ = *program;
    auto upload = [](Shape& s, const Vertices& v) {
        glGenVertexArrays(1, &s.vao);
        glGenBuffers(1, &s.vbo);
        glBindVertexArray(s.vao);
        glBindBuffer(GL_ARRAY_BUFFER, s.vbo);
        glBufferData(GL_ARRAY_BUFFER, v.size() * sizeof(float), v.data(), GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                              reinterpret_cast<void*>(3 * sizeof(float)));
        glBindVertexArray(0);
        s.count = static_cast<int>(v.size() / 6);
    };
    upload(d->sphere_, unitSphere(32, 16));
    upload(d->cylinder_, unitCylinder(16));
    upload(d->cube_, unitCube());
    return d;
}

GraphDrawer::~GraphDrawer() {
    for (Shape* s : {&sphere_, &cylinder_, &cube_}) {
        glDeleteVertexArrays(1, &s->vao);
        glDeleteBuffers(1, &s->vbo);
    }
    glDeleteProgram(program_);
}

void GraphDrawer::drawShape(const Shape& shape, const Eigen::Matrix4f& model,
                            const Eigen::Vector3f& colour, const Eigen::Vector3f& waterColour,
                            float level) {
    glUniformMatrix4fv(glGetUniformLocation(program_, "uModel"), 1, GL_FALSE, model.data());
    glUniform3fv(glGetUniformLocation(program_, "uColour"), 1, colour.data());
    glUniform3fv(glGetUniformLocation(program_, "uWater"), 1, waterColour.data());
    glUniform1f(glGetUniformLocation(program_, "uLevel"), level);
    glBindVertexArray(shape.vao);
    glDrawArrays(GL_TRIANGLES, 0, shape.count);
}

void GraphDrawer::draw(const RenderGraph& r, const Eigen::Matrix4f& viewProj,
                       const Camera& camera) {
    if (!r.graph) return;
    const WaterGraph& g = *r.graph;
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glUseProgram(program_);
    glUniformMatrix4fv(glGetUniformLocation(program_, "uViewProj"), 1, GL_FALSE, viewProj.data());
    const Eigen::Vector3f eye = camera.eye().cast<float>();
    glUniform3fv(glGetUniformLocation(program_, "uEye"), 1, eye.data());
    const Eigen::Matrix3d& R = r.pose.rotation;
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        const GraphNode& n = g.nodes[i];
        const bool selected = i < r.selectedNodes.size() && r.selectedNodes[i];
        const Eigen::Vector3f colour =
            selected ? Eigen::Vector3f(nodeColour(i) * 0.4f + Eigen::Vector3f::Constant(0.6f))
                     : nodeColour(i);
        // The water: the node's colour darkened toward deep blue.
        const Eigen::Vector3f water = nodeColour(i) * 0.35f + Eigen::Vector3f(0.0f, 0.1f, 0.45f);
        const double fill = i < r.water.size() ? r.water[i] : n.water;
        const Eigen::Vector3d centre = r.pose.apply(n.position);
        double level;
        Eigen::Matrix4f model;
        if (n.isBox()) {
            // The box's world height span, filled in proportion (the level of a box scaled to
            // the capacity, as the simulation's free-surface model has it, for an upright box).
            const double half = 0.5 * (R.cwiseAbs() * n.boxSize).y();
            level = centre.y() - half + 2 * half * std::clamp(fill / n.capacity, 0.0, 1.0);
            model = affine(R * n.boxSize.asDiagonal(), centre);
            drawShape(cube_, model, colour, water, float(level));
        } else {
            const double radius = sphereRadiusOfVolume(n.capacity);
            level = centre.y() - radius + sphereCapHeight(radius, fill);
            if (fill <= 0) level = centre.y() - 2 * radius;  // nothing below: no water colour
            model = affine(R * radius, centre);
            drawShape(sphere_, model, colour, water, float(level));
        }
    }
    // Pipe ends by hash: indexOf scans the nodes, and a frame drew every pipe.
    std::unordered_map<std::string, int> indexById;
    for (std::size_t n = 0; n < g.nodes.size(); ++n)
        indexById.emplace(g.nodes[n].id, static_cast<int>(n));
    for (std::size_t i = 0; i < g.pipes.size(); ++i) {
        const GraphPipe& p = g.pipes[i];
        const auto ia = indexById.find(p.a), ib = indexById.find(p.b);
        if (ia == indexById.end() || ib == indexById.end()) continue;
        const int a = ia->second, b = ib->second;
        const Eigen::Vector3d pa = r.pose.apply(g.nodes[a].position);
        const Eigen::Vector3d pb = r.pose.apply(g.nodes[b].position);
        const Eigen::Vector3d axis = pb - pa;
        const double length = axis.norm();
        if (length <= 0) continue;
        const Eigen::Vector3d z = axis / length;
        const Eigen::Vector3d helper =
            std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
        const Eigen::Vector3d x = helper.cross(z).normalized(), y = z.cross(x);
        // A closed pipe is drawn at half its radius in dark red; an open one light grey.
        // Thin pipes get a minimum on-screen thickness.
        const double radius = std::max(p.open ? p.radius : 0.5 * p.radius, camera.distance * 0.002);
        Eigen::Matrix3d frame;
        frame << x * radius, y * radius, z * length;
        const bool selected = static_cast<int>(i) == r.selectedPipe;
        const Eigen::Vector3f colour = selected ? Eigen::Vector3f(1.0f, 1.0f, 0.4f)
                                       : p.open ? Eigen::Vector3f(0.85f, 0.85f, 0.85f)
                                                : Eigen::Vector3f(0.55f, 0.08f, 0.08f);
        drawShape(cylinder_, affine(frame, pa), colour, colour, -1e30f);
    }
    glBindVertexArray(0);
}

}  // namespace plimsoll::editor
