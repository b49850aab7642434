#include "render/renderer.h"

#include "render/gl_program.h"
#include "render/shaders.h"
#include "view/water_view.h"

#include "plimsoll/geometry/validate.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace plimsoll::editor {

namespace {

void setMatrix(GLuint program, const char* name, const Eigen::Matrix4f& m) {
    glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m.data());
}

void pushLine(std::vector<float>& v, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
              const Eigen::Vector4f& c) {
    for (const Eigen::Vector3f* p : {&a, &b}) {
        v.insert(v.end(), {p->x(), p->y(), p->z(), c.x(), c.y(), c.z(), c.w()});
    }
}

void setupPositionColourVao(GLuint vao, GLuint vbo) {
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 7 * sizeof(float),
                          reinterpret_cast<void*>(3 * sizeof(float)));
    glBindVertexArray(0);
}

}  // namespace

// --- OffscreenTarget -----------------------------------------------------------------------------

Result<std::unique_ptr<OffscreenTarget>> OffscreenTarget::create(int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        return makeError(ErrorKind::invalidArgument, "image size must be 1..16384 pixels a side");
    }
    std::unique_ptr<OffscreenTarget> t(new OffscreenTarget());
    t->width_ = width;
    t->height_ = height;
    glGenFramebuffers(1, &t->framebuffer_);
    glGenRenderbuffers(1, &t->colour_);
    glGenRenderbuffers(1, &t->depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, t->colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, t->depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, t->framebuffer_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->colour_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth_);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        return makeError(ErrorKind::device, "offscreen framebuffer incomplete");
    }
    return t;
}

OffscreenTarget::~OffscreenTarget() {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteRenderbuffers(1, &colour_);
    glDeleteRenderbuffers(1, &depth_);
}

void OffscreenTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_); }

std::vector<std::uint8_t> OffscreenTarget::readRgba() const {
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width_) * height_ * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    // GL's row 0 is the bottom.
    const std::size_t row = static_cast<std::size_t>(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y) {
        std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row,
                         pixels.begin() + (height_ - 1 - y) * row);
    }
    return pixels;
}

// --- Renderer ------------------------------------------------------------------------------------

Result<std::unique_ptr<Renderer>> Renderer::create() {
    std::unique_ptr<Renderer> r(new Renderer());
    Result<unsigned> mesh = linkGlProgram({shaders::mesh_vert, shaders::water_view_vert},
                                          {shaders::mesh_frag, shaders::water_view_frag});
    if (!mesh) return mesh.error();
    r->meshProgram_ = *mesh;
    Result<unsigned> line = linkGlProgram({shaders::line_vert, shaders::water_view_vert},
                                          {shaders::line_frag, shaders::water_view_frag});
    if (!line) return line.error();
    r->lineProgram_ = *line;
    glGenVertexArrays(1, &r->lineVao_);
    glGenBuffers(1, &r->lineVbo_);
    setupPositionColourVao(r->lineVao_, r->lineVbo_);
    // water_view.frag's block and heights; no water until a scene with water is drawn.
    glGenBuffers(1, &r->waterBlock_);
    r->setWaterBlock(nullptr);
    glGenTextures(1, &r->waterHeights_);
    glBindTexture(GL_TEXTURE_2D, r->waterHeights_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    return r;
}

Renderer::~Renderer() {
    for (auto& [_, m] : meshes_) {
        glDeleteVertexArrays(1, &m.vao);
        glDeleteBuffers(1, &m.vbo);
    }
    for (auto& [_, o] : overlays_) glDeleteTextures(1, &o.texture);
    for (auto& [_, w] : wireframes_) glDeleteTextures(1, &w.texture);
    glDeleteVertexArrays(1, &lineVao_);
    glDeleteBuffers(1, &lineVbo_);
    glDeleteBuffers(1, &waterBlock_);
    glDeleteTextures(1, &waterHeights_);
    glDeleteProgram(meshProgram_);
    glDeleteProgram(lineProgram_);
}

const WaterView* Renderer::waterViewOf(const RenderScene& scene, const Camera& camera) {
    if (!scene.water) return nullptr;
    WaterCache& c = waterCache_;
    const std::uint64_t generation = waterGeneration(*scene.water);
    if (c.generation != generation || c.time != scene.time ||
        c.view.camera.target != camera.target || c.view.camera.distance != camera.distance) {
        c.generation = generation;
        c.time = scene.time;
        c.view = WaterView::of(*scene.water, scene.time, camera);
        c.uploaded = false;
    }
    c.view.camera = camera;  // the heights follow only the target and the distance
    return &c.view;
}

std::uint64_t Renderer::waterGeneration(const WaterModel& water) {
    if (!(lastWater_ && *lastWater_ == water)) {
        lastWater_ = water;
        ++waterGeneration_;
    }
    return waterGeneration_;
}

Eigen::Vector3f Renderer::backdropColour(const RenderScene& scene, bool seenThroughWater) {
    return seenThroughWater ? throughWater(scene.background, kWaterColour, kWaterOpacity)
                            : scene.background;
}

Eigen::Vector3f Renderer::clearColour(const RenderScene& scene, const Camera& camera, int width,
                                      int height) {
    const WaterView* view = waterViewOf(scene, camera);
    if (!view) return scene.background;
    return backdropColour(scene, view->backdrop(width, height).largerSeenThrough());
}

void Renderer::setWaterBlock(const WaterView* view) {
    WaterBlock block{};
    if (view) {
        const Eigen::Vector3d eye = view->camera.eye(), forward = view->camera.forward();
        block = {{kWaterColour.x(), kWaterColour.y(), kWaterColour.z(), kWaterOpacity},
                 {float(view->x0), float(view->z0), float(view->step), float(WaterView::kCells)},
                 {float(eye.x()), float(eye.y()), float(eye.z()),
                  view->camera.orthographic ? 1.0f : 0.0f},
                 {float(forward.x()), float(forward.y()), float(forward.z()), 0.0f}};
    }
    // New storage each time (64 bytes), not a write into the old: llvmpipe would first wait
    // for the draws still queued that read it.
    glBindBuffer(GL_UNIFORM_BUFFER, waterBlock_);
    glBufferData(GL_UNIFORM_BUFFER, sizeof block, &block, GL_STREAM_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, kWaterBlockBinding, waterBlock_);
}

Renderer::MeshBuffers& Renderer::buffersFor(const std::shared_ptr<const TriangleMesh>& mesh) {
    // Drop buffers of meshes that are gone.
    for (auto it = meshes_.begin(); it != meshes_.end();) {
        if (it->second.owner.expired()) {
            glDeleteVertexArrays(1, &it->second.vao);
            glDeleteBuffers(1, &it->second.vbo);
            it = meshes_.erase(it);
        } else {
            ++it;
        }
    }
    MeshBuffers& b = meshes_[mesh.get()];
    if (b.vao) return b;
    b.owner = mesh;
    // Position, uv and the triangle's unit normal for each of its three vertices.
    constexpr int kFloats = 8;
    std::vector<float> vertices;
    vertices.reserve(mesh->triangles.size() * 3 * kFloats);
    const bool uvs = mesh->hasUvs();
    for (const Triangle& t : mesh->triangles) {
        const Eigen::Vector3d& a = mesh->positions[t[0]];
        const Eigen::Vector3d normal =
            (mesh->positions[t[1]] - a).cross(mesh->positions[t[2]] - a).normalized();
        for (std::uint32_t v : t) {
            const Eigen::Vector3d& p = mesh->positions[v];
            const Eigen::Vector2d uv = uvs ? mesh->uvs[v] : Eigen::Vector2d::Zero();
            vertices.insert(vertices.end(),
                            {float(p.x()), float(p.y()), float(p.z()), float(uv.x()), float(uv.y()),
                             float(normal.x()), float(normal.y()), float(normal.z())});
        }
    }
    b.vertexCount = static_cast<int>(mesh->triangles.size() * 3);
    b.closedSolid = validateSurface(*mesh).closedSolid();
    glGenVertexArrays(1, &b.vao);
    glGenBuffers(1, &b.vbo);
    glBindVertexArray(b.vao);
    glBindBuffer(GL_ARRAY_BUFFER, b.vbo);
    glBufferData(GL_ARRAY_BUFFER, vertices.size() * sizeof(float), vertices.data(), GL_STATIC_DRAW);
    const GLsizei stride = kFloats * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<void*>(5 * sizeof(float)));
    glBindVertexArray(0);
    return b;
}

void Renderer::setOverlay(int slot, const OverlayImage& image) {
    Overlay& o = overlays_[slot];
    if (image.width == 0) {
        textureVersions_.erase(o.texture);
        glDeleteTextures(1, &o.texture);
        overlays_.erase(slot);
        return;
    }
    if (!o.texture) glGenTextures(1, &o.texture);
    textureVersions_[o.texture] = ++textureUploads_;
    glBindTexture(GL_TEXTURE_2D, o.texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, image.rgba.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    o.scale = Eigen::Vector2f::Constant(static_cast<float>(image.placement.scale));
    o.offset = image.placement.offset.cast<float>();
}

unsigned Renderer::overlayTexture(int slot) const {
    auto it = overlays_.find(slot);
    return it == overlays_.end() ? 0 : it->second.texture;
}

std::optional<std::uint64_t> Renderer::textureVersion(unsigned texture) const {
    auto it = textureVersions_.find(texture);
    if (it == textureVersions_.end()) return std::nullopt;
    return it->second;
}

unsigned Renderer::uvWireframeTexture(const std::shared_ptr<const TriangleMesh>& mesh, int size) {
    if (!mesh || !mesh->hasUvs() || size < 1) return 0;
    for (auto it = wireframes_.begin(); it != wireframes_.end();) {
        if (it->second.owner.expired()) {
            textureVersions_.erase(it->second.texture);
            glDeleteTextures(1, &it->second.texture);
            it = wireframes_.erase(it);
        } else {
            ++it;
        }
    }
    Wireframe& w = wireframes_[mesh.get()];
    if (w.texture && w.size == size) return w.texture;
    w.owner = mesh;
    w.size = size;
    if (!w.texture) glGenTextures(1, &w.texture);
    textureVersions_[w.texture] = ++textureUploads_;
    glBindTexture(GL_TEXTURE_2D, w.texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    GLint previous = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previous);
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    GLuint framebuffer = 0;
    glGenFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, w.texture, 0);
    glViewport(0, 0, size, size);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    std::vector<float> lines;
    lines.reserve(mesh->triangles.size() * 6 * 7);
    const Eigen::Vector4f colour(1, 1, 1, 0.3f);
    for (const Triangle& t : mesh->triangles) {
        for (int e = 0; e < 3; ++e) {
            const Eigen::Vector2d a = mesh->uvs[t[e]] * 2.0 - Eigen::Vector2d::Ones();
            const Eigen::Vector2d b = mesh->uvs[t[(e + 1) % 3]] * 2.0 - Eigen::Vector2d::Ones();
            pushLine(lines, {float(a.x()), float(a.y()), 0}, {float(b.x()), float(b.y()), 0},
                     colour);
        }
    }
    setWaterBlock(nullptr);  // UVs, not the world: nothing is seen through water here
    drawLines(lines, Eigen::Matrix4f::Identity());
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, previous);
    glDeleteFramebuffers(1, &framebuffer);
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    return w.texture;
}

void Renderer::drawLines(const std::vector<float>& vertices, const Eigen::Matrix4f& viewProj) {
    if (vertices.empty()) return;
    glUseProgram(lineProgram_);
    setMatrix(lineProgram_, "uViewProj", viewProj);
    glBindVertexArray(lineVao_);
    glBindBuffer(GL_ARRAY_BUFFER, lineVbo_);
    glBufferData(GL_ARRAY_BUFFER, vertices.size() * sizeof(float), vertices.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(vertices.size() / 7));
}

Renderer::SceneKey Renderer::keyOf(const RenderScene& scene, const Camera& camera, int width,
                                   int height) {
    SceneKey key;
    std::vector<double>& n = key.numbers;
    n.reserve(32 + scene.bodies.size() * 16);
    n.insert(n.end(),
             {double(width), double(height), camera.target.x(), camera.target.y(),
              camera.target.z(), camera.yaw, camera.pitch, camera.distance, camera.fovY,
              double(camera.orthographic), scene.time, double(scene.grid), double(scene.axes),
              scene.background.x(), scene.background.y(), scene.background.z()});
    n.push_back(scene.water ? double(waterGeneration(*scene.water)) : -1.0);
    n.insert(n.end(), {scene.floor ? 1.0 : 0.0, scene.floor.value_or(0.0)});
    for (const RenderBody& body : scene.bodies) {
        key.meshes.push_back(body.mesh.get());
        n.insert(n.end(), body.pose.rotation.data(), body.pose.rotation.data() + 9);
        n.insert(n.end(), body.pose.translation.data(), body.pose.translation.data() + 3);
        // The overlay the body shows, by its slot and what its texture holds.
        const unsigned overlay = overlayTexture(body.overlay);
        const std::optional<std::uint64_t> version =
            overlay ? textureVersion(overlay) : std::nullopt;
        n.insert(n.end(), {double(body.overlay), version ? double(*version) : -1.0,
                           double(body.selected), double(body.alpha)});
    }
    return key;
}

bool Renderer::drawIntoCache(const RenderScene& scene, const Camera& camera, int width,
                             int height) {
    if ((cache_.image.width() != width || cache_.image.height() != height) &&
        !cache_.image.resize(width, height, /*depth=*/true)) {
        return false;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, cache_.image.framebuffer());
    glViewport(0, 0, width, height);
    glDisable(GL_SCISSOR_TEST);
    const Eigen::Vector3f clear = clearColour(scene, camera, width, height);
    glClearColor(clear.x(), clear.y(), clear.z(), 1.0f);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    // Upside down: the kept image holds the window's rows in the window's order (WindowImage).
    drawScene(scene, camera, width, height, /*upsideDown=*/true);
    return true;
}

void Renderer::draw(const RenderScene& scene, const Camera& camera, int width, int height, int x,
                    int y, bool cleared) {
    std::optional<SceneKey> key;
    if (!scene.drawInside) key = keyOf(scene, camera, width, height);
    const bool copy = key && cache_.kept && *cache_.kept == *key;
    // The same scene as last frame: draw it once more into the kept texture, then copy.
    const bool keep = key && !copy && cache_.previous && *cache_.previous == *key;
    cache_.previous = key;
    GLint target = 0, read = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    auto restoreTargets = [&] {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, read);
    };
    auto drawDirectly = [&] {
        ++framesDrawn_;
        glViewport(x, y, width, height);
        glClearDepth(1.0);
        glDepthMask(GL_TRUE);
        if (cleared) {
            // The depth of the whole target (no one else reads it), with the stencil: a
            // depth-only clear of a depth-stencil buffer rewrites each pixel's depth bits
            // and keeps its stencil bits, 2.4 ms at 1600 x 900 on llvmpipe; the two
            // together are one fill.
            glDisable(GL_SCISSOR_TEST);
            glClearStencil(0);
            glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
        }
        glScissor(x, y, width, height);
        glEnable(GL_SCISSOR_TEST);
        // A scissored clear is a quad drawn over the rectangle on llvmpipe (a whole-target
        // clear is not): callers that clear the whole target skip it.
        if (!cleared) {
            const Eigen::Vector3f clear = clearColour(scene, camera, width, height);
            glClearColor(clear.x(), clear.y(), clear.z(), 1.0f);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        }
        drawScene(scene, camera, width, height);
    };
    if (!copy && !keep) {
        cache_.kept.reset();
        drawDirectly();
        if (key && cache_.warmUp) {
            // Once, at the first scene: the same scene into the kept texture as well, and
            // copied over the one just drawn (the same pixels). llvmpipe compiles shaders for
            // the texture as a target and for the copy the first time each is used: 60-160 ms
            // of one frame on 2 busy cores. Paid here, at start-up, it is not paid in the
            // first frame the view stands still after an edit (a new texture size
            // must never block a frame for more than 50 ms).
            cache_.warmUp = false;
            if (drawIntoCache(scene, camera, width, height)) {
                cache_.kept = key;
                cache_.image.copyTo(target, x, y);
            }
            restoreTargets();
            glViewport(x, y, width, height);
        }
        return;
    }
    if (keep) {
        if (!drawIntoCache(scene, camera, width, height)) {
            // No kept scene on this driver: draw it as before.
            restoreTargets();
            cache_.previous.reset();
            drawDirectly();
            return;
        }
        ++framesDrawn_;
        cache_.kept = key;
    } else {
        ++framesCopied_;
    }
    cache_.image.copyTo(target, x, y);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, read);
}

void Renderer::drawLinesOf(const RenderScene& scene, const Camera& camera, const WaterView* water,
                           const Eigen::Matrix4f& viewProj) {
    // Grid (1 m, on y = 0; on waves the water's surface instead) and axes. On waves, in pieces of
    // at most a cell of the water's heights: a line's side of the water is worked out at its
    // vertices (water_view.vert).
    std::vector<float>& lines = frameLines_;
    lines.clear();
    const float extent =
        static_cast<float>(std::clamp(std::ceil(camera.distance * 2.0), 2.0, 200.0));
    const float piece = water && scene.water->kind != WaterModel::Kind::Flat
                            ? static_cast<float>(water->step)
                            : 2 * extent;
    auto pushPieces = [&](const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                          const Eigen::Vector4f& colour) {
        const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / piece)));
        for (int k = 0; k < pieces; ++k) {
            pushLine(lines, a + (b - a) * (float(k) / pieces),
                     a + (b - a) * (float(k + 1) / pieces), colour);
        }
    };
    // On waves the grid is the water's surface, a net of the view's height samples, each
    // vertex at the wave function's height there (WaterView::surfaceSegments): lighter toward
    // the crests. Lines cost llvmpipe next to nothing where a filled sheet cost 5 ms a frame.
    const bool waves = water && scene.water->kind != WaterModel::Kind::Flat;
    if (scene.grid && waves) {
        const auto [low, high] = std::minmax_element(water->heights.begin(), water->heights.end());
        const float range = std::max(*high - *low, 1e-6f);
        // A millimetre toward the eye's side: the net is not tinted as seen through itself.
        const float lift = water->below(camera.eye()) ? -1e-3f : 1e-3f;
        std::vector<Eigen::Vector3f>& net = frameNet_;
        water->surfaceSegments(lift, net);
        lines.reserve(net.size() * 7);
        const Eigen::Vector4f trough(0.16f, 0.42f, 0.62f, 1.0f), crest(0.70f, 0.88f, 0.97f, 1.0f);
        // Out to the grid's own reach around the view's centre (the heights reach further).
        const Eigen::Vector2f centre(float(camera.target.x()), float(camera.target.z()));
        auto near = [&](const Eigen::Vector3f& p) {
            return (Eigen::Vector2f(p.x(), p.z()) - centre).cwiseAbs().maxCoeff() <= extent;
        };
        for (std::size_t k = 0; k + 1 < net.size(); k += 2) {
            if (!near(net[k]) && !near(net[k + 1])) continue;
            const float t = std::clamp((0.5f * (net[k].y() + net[k + 1].y()) - lift - *low) / range,
                                       0.0f, 1.0f);
            pushLine(lines, net[k], net[k + 1], trough + t * (crest - trough));
        }
    } else if (scene.grid) {
        const Eigen::Vector4f grey(0.45f, 0.45f, 0.45f, 1.0f);
        const int n = static_cast<int>(extent);
        for (int i = -n; i <= n; ++i) {
            if (i == 0 && scene.axes) continue;
            pushPieces({float(i), 0, -extent}, {float(i), 0, extent}, grey);
            pushPieces({-extent, 0, float(i)}, {extent, 0, float(i)}, grey);
        }
    }
    if (scene.floor) {
        // The sea floor: a 2 m grid straight below the view's centre.
        const Eigen::Vector4f sand(0.62f, 0.55f, 0.40f, 1.0f);
        const float y = static_cast<float>(*scene.floor);
        const float cx = 2 * std::round(float(camera.target.x()) / 2);
        const float cz = 2 * std::round(float(camera.target.z()) / 2);
        const int n = static_cast<int>(extent / 2);
        // A floor below the lowest trough is wholly on one side of the water: whole lines, not
        // pieces of a cell (half the floor's cost on llvmpipe).
        const bool below = !scene.water || *scene.floor < scene.water->minHeight();
        for (int i = -n; i <= n; ++i) {
            const Eigen::Vector3f a(cx + 2.0f * i, y, cz - extent),
                b(cx + 2.0f * i, y, cz + extent);
            const Eigen::Vector3f c(cx - extent, y, cz + 2.0f * i),
                d(cx + extent, y, cz + 2.0f * i);
            if (below) {
                pushLine(lines, a, b, sand);
                pushLine(lines, c, d, sand);
            } else {
                pushPieces(a, b, sand);
                pushPieces(c, d, sand);
            }
        }
    }
    if (scene.axes) {
        pushPieces({-extent, 0, 0}, {extent, 0, 0}, {0.85f, 0.25f, 0.25f, 1});
        pushPieces({0, 0, -extent}, {0, 0, extent}, {0.25f, 0.45f, 0.90f, 1});
        pushPieces({0, 0, 0}, {0, 1, 0}, {0.35f, 0.80f, 0.35f, 1});
    }
    drawLines(lines, viewProj);
}

void Renderer::drawScene(const RenderScene& scene, const Camera& camera, int width, int height,
                         bool upsideDown) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    // Only opaque closed solids are culled (drawBodies); a mirrored image turns the winding
    // the eye sees.
    glDisable(GL_CULL_FACE);
    glFrontFace(upsideDown ? GL_CW : GL_CCW);
    glDisable(GL_BLEND);
    Eigen::Matrix4f viewProj =
        (camera.projection(double(width) / std::max(height, 1)) * camera.view()).cast<float>();
    if (upsideDown) viewProj.row(1) *= -1.0f;  // clip y reversed; shading uses |n.v|

    // The water: the smaller part of the background (the larger is the clear), and what the
    // shaders need to tint what is seen through it (water_view.h).
    const WaterView* water = waterViewOf(scene, camera);
    setWaterBlock(water);
    if (water) {
        if (!waterCache_.uploaded) {
            glBindTexture(GL_TEXTURE_2D, waterHeights_);
            glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, WaterView::kCells + 1, WaterView::kCells + 1, 0,
                         GL_RED, GL_FLOAT, water->heights.data());
            waterCache_.uploaded = true;
        }
        glActiveTexture(GL_TEXTURE0 + kWaterHeightsUnit);
        glBindTexture(GL_TEXTURE_2D, waterHeights_);
        glActiveTexture(GL_TEXTURE0);
        // The smaller part's rows, counted from the top, then in GL's rows from the bottom
        // (the upside-down image has the top at the bottom).
        const WaterView::Backdrop b = water->backdrop(width, height);
        const int first = b.smallerFirstRow(), rows = b.smallerRows();
        if (rows > 0) {
            GLint viewport[4], scissor[4];
            glGetIntegerv(GL_VIEWPORT, viewport);
            glGetIntegerv(GL_SCISSOR_BOX, scissor);
            const GLboolean scissored = glIsEnabled(GL_SCISSOR_TEST);
            const int bottom = upsideDown ? first : height - first - rows;
            glEnable(GL_SCISSOR_TEST);
            glScissor(viewport[0], viewport[1] + bottom, width, rows);
            const Eigen::Vector3f colour = backdropColour(scene, !b.largerSeenThrough());
            glClearColor(colour.x(), colour.y(), colour.z(), 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            glScissor(scissor[0], scissor[1], scissor[2], scissor[3]);
            if (!scissored) glDisable(GL_SCISSOR_TEST);
        }
    }

    // Bodies.
    glUseProgram(meshProgram_);
    setMatrix(meshProgram_, "uViewProj", viewProj);
    const Eigen::Vector3f eye = camera.eye().cast<float>();
    const Eigen::Vector3f viewDir = camera.forward().cast<float>();
    glUniform3fv(glGetUniformLocation(meshProgram_, "uEye"), 1, eye.data());
    glUniform3fv(glGetUniformLocation(meshProgram_, "uViewDir"), 1, viewDir.data());
    glUniform1i(glGetUniformLocation(meshProgram_, "uOrtho"), camera.orthographic ? 1 : 0);
    glUniform1i(glGetUniformLocation(meshProgram_, "uOverlay"), 0);
    // Opaque bodies, then what is inside them, then the see-through ones over it.
    auto drawBodies = [&](bool seeThrough) {
        for (const RenderBody& body : scene.bodies) {
            if (!body.mesh || (body.alpha < 1.0f) != seeThrough) continue;
            glUniform1f(glGetUniformLocation(meshProgram_, "uAlpha"), body.alpha);
            Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
            model.block<3, 3>(0, 0) = body.pose.rotation.cast<float>();
            model.block<3, 1>(0, 3) = body.pose.translation.cast<float>();
            setMatrix(meshProgram_, "uModel", model);
            auto overlay = overlays_.find(body.overlay);
            const bool hasOverlay = overlay != overlays_.end() && body.mesh->hasUvs();
            glUniform1i(glGetUniformLocation(meshProgram_, "uHasOverlay"), hasOverlay ? 1 : 0);
            if (hasOverlay) {
                glActiveTexture(GL_TEXTURE0);
                glBindTexture(GL_TEXTURE_2D, overlay->second.texture);
                glUniform2fv(glGetUniformLocation(meshProgram_, "uUvScale"), 1,
                             overlay->second.scale.data());
                glUniform2fv(glGetUniformLocation(meshProgram_, "uUvOffset"), 1,
                             overlay->second.offset.data());
            }
            const Eigen::Vector3f base = body.selected ? Eigen::Vector3f(0.80f, 0.78f, 0.72f)
                                                       : Eigen::Vector3f(0.70f, 0.70f, 0.70f);
            glUniform3fv(glGetUniformLocation(meshProgram_, "uBase"), 1, base.data());
            MeshBuffers& b = buffersFor(body.mesh);
            // A see-through body shows its far side through the near one: nothing is culled.
            if (b.closedSolid && !seeThrough) glEnable(GL_CULL_FACE);
            glBindVertexArray(b.vao);
            glDrawArrays(GL_TRIANGLES, 0, b.vertexCount);
            glDisable(GL_CULL_FACE);
        }
    };
    drawBodies(false);
    if (scene.drawInside) {
        scene.drawInside(viewProj);
        glUseProgram(meshProgram_);
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    // Pulled a little toward the eye: where what is inside touches the hull (a compartment's
    // box top in the deck's plane), the see-through hull lies over it everywhere instead of
    // in a speckle of the pixels that happen to round nearer (z-fighting).
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1.0f, -4.0f);
    drawBodies(true);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);

    drawLinesOf(scene, camera, water, viewProj);

    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_SCISSOR_TEST);
    glFrontFace(GL_CCW);
}

}  // namespace plimsoll::editor
