// PanelCache (editor/app/panel_cache.h): the column's panels are copied from a kept image while
// they stay the same. Every frame it draws must equal ImGui's own drawing of the same frame,
// pixel for pixel, whatever changes: text in a panel, a texture a panel shows, a window
// outside the column, a window behind the panels reaching into the column, one in front of
// them. Headless (EGL); skipped where no OpenGL 4.5 context can be made.
#include "app/panel_cache.h"
#include "headless_gl_test.h"
#include "render/renderer.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include <string>

namespace plimsoll::editor {
namespace test_editor_panel_cache {
namespace {

constexpr int kWidth = 320, kHeight = 240;
const ImVec4 kBackground(0.20f, 0.21f, 0.23f, 1.0f);

/// What one frame shows: the column's two panels and a floating window.
struct Frame {
    std::string panelText = "Radius 0.050";
    std::uint64_t imageVersion = 1;
    ImVec2 floatingAt{10, 10};
    std::string floatingText = "t = 0.00";
    bool tooltipOverColumn = false;
};

class PanelCacheTest : public test::HeadlessGlTest {
protected:
    void SetUp() override {
        HeadlessGlTest::SetUp();
        if (IsSkipped()) return;
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(kWidth, kHeight);
        io.DeltaTime = 1.0f / 60.0f;
        ImGui::StyleColorsDark();
        ASSERT_TRUE(ImGui_ImplOpenGL3_Init("#version 450 core"));
        for (auto* target : {&cached_, &direct_}) {
            Result<std::unique_ptr<OffscreenTarget>> t = OffscreenTarget::create(kWidth, kHeight);
            ASSERT_TRUE(t.ok()) << t.error().message;
            *target = std::move(t).value();
        }
        // A texture a panel shows, whose version the test sets.
        glGenTextures(1, &image_);
        glBindTexture(GL_TEXTURE_2D, image_);
        const unsigned char texels[16] = {255, 0, 0,   255, 0,   255, 0,   255,
                                          0,   0, 255, 255, 255, 255, 255, 255};
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        cache_ = std::make_unique<PanelCache>();
        ready_ = true;
    }
    void TearDown() override {
        if (!ready_) return;
        cache_.reset();
        cached_.reset();
        direct_.reset();
        glDeleteTextures(1, &image_);
        ImGui_ImplOpenGL3_Shutdown();
        ImGui::DestroyContext();
    }

    /// Builds `frame` with ImGui, draws it through the cache and directly, and says whether
    /// the two images are the same.
    ::testing::AssertionResult drawsAsImGuiDoes(const Frame& frame) {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui::NewFrame();
        const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                       ImGuiWindowFlags_NoCollapse |
                                       ImGuiWindowFlags_NoSavedSettings;
        // Begun first, so that on the first frame it is behind the panels.
        ImGui::SetNextWindowPos(frame.floatingAt);
        ImGui::SetNextWindowSize(ImVec2(120, 80));
        ImGui::Begin("Floating", nullptr, fixed | ImGuiWindowFlags_NoBringToFrontOnFocus);
        ImGui::TextUnformatted(frame.floatingText.c_str());
        ImGui::End();
        ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
        ImGui::SetNextWindowPos(ImVec2(column_.x, 0));
        ImGui::SetNextWindowSize(ImVec2(column_.z - column_.x, 120.5f));
        ImGui::Begin("Tools", nullptr, fixed);
        ImGui::TextUnformatted(frame.panelText.c_str());
        ImGui::Button("Apply");
        ImGui::End();
        ImGui::SetNextWindowPos(ImVec2(column_.x, 120.5f));
        ImGui::SetNextWindowSize(ImVec2(column_.z - column_.x, 119.5f));
        ImGui::Begin("UV view", nullptr, fixed);
        ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image_)),
                     ImVec2(64, 64));
        ImGui::End();
        ImGui::PopStyleVar();
        if (frame.tooltipOverColumn) {
            // In front of everything, half over the column.
            ImGui::GetForegroundDrawList()->AddRectFilled(ImVec2(150, 60), ImVec2(260, 90),
                                                          IM_COL32(200, 180, 40, 220));
        }
        ImGui::Render();
        const ImTextureID font = ImGui::GetIO().Fonts->TexID;
        const ImTextureID image = reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(image_));
        auto version = [&](ImTextureID texture) -> std::optional<std::uint64_t> {
            if (texture == font) return 0;
            if (texture == image) return frame.imageVersion;
            return std::nullopt;
        };
        auto clear = [] {
            glDisable(GL_SCISSOR_TEST);
            glClearColor(kBackground.x, kBackground.y, kBackground.z, kBackground.w);
            glClear(GL_COLOR_BUFFER_BIT);
        };
        cached_->bind();
        clear();
        cache_->render(*ImGui::GetDrawData(), column_, kBackground, version);
        const std::vector<std::uint8_t> viaCache = cached_->readRgba();
        direct_->bind();
        clear();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        const std::vector<std::uint8_t> byImGui = direct_->readRgba();
        std::size_t differing = 0;
        for (std::size_t i = 0; i < viaCache.size(); ++i) differing += viaCache[i] != byImGui[i];
        if (differing == 0) return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << differing << " bytes differ";
    }

    /// The column: whole pixels, or (a column split at a fraction of the window) not.
    ImVec4 column_{200, 0, 320, 240};
    std::unique_ptr<OffscreenTarget> cached_, direct_;
    std::unique_ptr<PanelCache> cache_;
    unsigned image_ = 0;
    bool ready_ = false;
};

TEST_F(PanelCacheTest, CopiesTheColumnOnlyWhileItStaysTheSameAndAlwaysDrawsWhatImGuiDraws) {
    Frame frame;
    // ImGui settles its windows in the first frames.
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(drawsAsImGuiDoes(frame));
    const std::uint64_t keptAtStart = cache_->framesKept();
    EXPECT_EQ(keptAtStart, 1u);

    // Only the window outside the column changes: the column is copied.
    std::uint64_t copied = cache_->framesCopied();
    for (int i = 0; i < 3; ++i) {
        frame.floatingText = "t = " + std::to_string(i);
        ASSERT_TRUE(drawsAsImGuiDoes(frame));
    }
    EXPECT_EQ(cache_->framesCopied(), copied + 3);

    // The panel's text changes: drawn, and kept again once it holds still.
    frame.panelText = "Radius 0.075";
    copied = cache_->framesCopied();
    ASSERT_TRUE(drawsAsImGuiDoes(frame));
    EXPECT_EQ(cache_->framesCopied(), copied);
    ASSERT_TRUE(drawsAsImGuiDoes(frame));
    EXPECT_EQ(cache_->framesKept(), keptAtStart + 1);
    ASSERT_TRUE(drawsAsImGuiDoes(frame));
    EXPECT_EQ(cache_->framesCopied(), copied + 1);

    // A texture a panel shows gets new contents (same name, new version): not copied.
    copied = cache_->framesCopied();
    frame.imageVersion = 2;
    ASSERT_TRUE(drawsAsImGuiDoes(frame));
    EXPECT_EQ(cache_->framesCopied(), copied);

    // Something in front of everything, half over the column: still the same pixels.
    frame.tooltipOverColumn = true;
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(drawsAsImGuiDoes(frame));
    frame.tooltipOverColumn = false;

    // The floating window, behind the panels, moved into the column; then its text changes
    // while the panels stay still.
    frame.floatingAt = ImVec2(150, 40);
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(drawsAsImGuiDoes(frame));
    for (int i = 0; i < 3; ++i) {
        frame.floatingText = "behind " + std::to_string(i);
        ASSERT_TRUE(drawsAsImGuiDoes(frame));
    }
}

TEST_F(PanelCacheTest, AColumnAtAFractionOfAPixelIsKeptToo) {
    column_.x = 200.4f;
    Frame frame;
    for (int i = 0; i < 5; ++i) {
        frame.floatingText = "t = " + std::to_string(i);
        ASSERT_TRUE(drawsAsImGuiDoes(frame));
    }
    EXPECT_EQ(cache_->framesKept(), 1u);
    EXPECT_GE(cache_->framesCopied(), 2u);
}

}  // namespace
}  // namespace test_editor_panel_cache
}  // namespace plimsoll::editor
