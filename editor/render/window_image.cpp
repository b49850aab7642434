#include "render/window_image.h"

#include <epoxy/gl.h>

namespace plimsoll::editor {
namespace {

/// Runs a blit with the scissor test off and the framebuffer bindings restored after:
/// `target` for drawing, the read binding as it was.
template <class Blit>
void blitWithoutScissor(int target, const Blit& blit) {
    GLint read = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    const bool scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST);
    blit();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(target));
    if (scissor) glEnable(GL_SCISSOR_TEST);
}

}  // namespace

WindowImage::~WindowImage() {
    if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
    if (colour_) glDeleteTextures(1, &colour_);
    if (depth_) glDeleteRenderbuffers(1, &depth_);
}

bool WindowImage::resize(int width, int height, bool depth) {
    if (!framebuffer_) {
        glGenFramebuffers(1, &framebuffer_);
        glGenTextures(1, &colour_);
    }
    GLint drawn = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawn);
    glBindTexture(GL_TEXTURE_2D, colour_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_BGRA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_);
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_, 0);
    if (depth) {
        if (!depth_) glGenRenderbuffers(1, &depth_);
        glBindRenderbuffer(GL_RENDERBUFFER, depth_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    }
    glFramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              depth ? depth_ : 0);
    const bool complete = glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(drawn));
    width_ = complete ? width : 0;
    height_ = complete ? height : 0;
    return complete;
}

void WindowImage::copyFrom(int target, int x, int y) {
    blitWithoutScissor(target, [&] {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(target));
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_);
        glBlitFramebuffer(x, y, x + width_, y + height_, 0, height_, width_, 0, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
    });
}

void WindowImage::copyTo(int target, int x, int y) const {
    blitWithoutScissor(target, [&] {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(target));
        glBlitFramebuffer(0, height_, width_, 0, x, y, x + width_, y + height_, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
    });
}

}  // namespace plimsoll::editor
