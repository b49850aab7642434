// Tests that draw with OpenGL 4.5 in a headless (EGL) context: the fixture makes the context and
// skips the test where none can be made (a machine without Mesa's EGL).
#pragma once

#include "render/headless_context.h"
#include "render/renderer.h"

#include "plimsoll/core/result.h"

#include <gtest/gtest.h>

#include <memory>

namespace plimsoll::test {

class HeadlessGlTest : public ::testing::Test {
protected:
    /// Makes the context current; a fixture that derives calls this first and returns when
    /// IsSkipped().
    void SetUp() override {
        Result<std::unique_ptr<editor::HeadlessContext>> made = editor::HeadlessContext::create();
        if (!made) GTEST_SKIP() << "no headless OpenGL 4.5 here: " << made.error().message;
        context = std::move(made).value();
    }
    /// Made first, so gone last: a derived fixture's GL objects go while it is current.
    std::unique_ptr<editor::HeadlessContext> context;
};

/// A renderer in the headless context (skipped where there is none).
class HeadlessRendererTest : public HeadlessGlTest {
protected:
    void SetUp() override {
        HeadlessGlTest::SetUp();
        if (IsSkipped()) return;
        Result<std::unique_ptr<editor::Renderer>> r = editor::Renderer::create();
        ASSERT_TRUE(r.ok()) << r.error().message;
        renderer = std::move(r).value();
    }
    std::unique_ptr<editor::Renderer> renderer;
};

}  // namespace plimsoll::test
