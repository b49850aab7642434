// An OpenGL 4.5 core context with no window and no display, through EGL: Mesa's surfaceless
// platform (llvmpipe on a machine with no GPU), or an EGL device (the NVIDIA driver), or the
// default display. Rendering goes into a framebuffer object (renderer.h, OffscreenTarget).
#pragma once

#include "plimsoll/core/result.h"

#include <memory>
#include <string>

namespace plimsoll::editor {

class HeadlessContext {
public:
    /// Creates the context and makes it current on this thread.
    static Result<std::unique_ptr<HeadlessContext>> create();
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    /// Which EGL platform and GL renderer it got ("surfaceless: llvmpipe (LLVM 15.0.6, 256 bits)").
    const std::string& description() const { return description_; }

private:
    HeadlessContext() = default;
    void* display_ = nullptr;
    void* context_ = nullptr;
    std::string description_;
};

}  // namespace plimsoll::editor
