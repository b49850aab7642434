// An image kept for a rectangle of the window, stored so that copying it to or from the window
// is a copy of rows: the kept 3D view (Renderer) and the kept panels (PanelCache).
//
// Why it is not a plain texture: Mesa keeps a window's rows top first and a texture's bottom
// first, so a plain glBlitFramebuffer between them turns the rows over, and llvmpipe does that
// with a textured quad (4.6 ms for a 1200 x 858 view on 2 cores). This image holds the window's
// rows in the window's order (what is drawn into it directly is drawn upside down), and every
// copy reads or writes it with its rows reversed: the two flips cancel. Its texture is unsized
// GL_RGBA given BGRA bytes, which Mesa stores as B8G8R8A8, the window's own layout (GL_RGBA8 is
// stored R8G8B8A8). llvmpipe then copies rows (0.8 ms for the same view). On another driver the
// copies are still right, only not necessarily as cheap.
#pragma once

namespace plimsoll::editor {

class WindowImage {
public:
    WindowImage() = default;
    ~WindowImage();
    WindowImage(const WindowImage&) = delete;
    WindowImage& operator=(const WindowImage&) = delete;

    /// Makes (or remakes) the image width x height, with a depth buffer if asked for; false
    /// where this driver cannot draw into it. Leaves the framebuffer binding as it was.
    bool resize(int width, int height, bool depth);
    int width() const { return width_; }
    int height() const { return height_; }
    /// Its framebuffer, to draw into (upside down: see the file comment).
    unsigned framebuffer() const { return framebuffer_; }

    /// The window's (framebuffer `target`'s) rectangle at (x, y) (GL's lower-left corner), of
    /// this image's size, into this image; and this image back into such a rectangle. Both
    /// leave `target` bound for drawing and the read binding as it was; the scissor test is off
    /// during the copy and restored after.
    void copyFrom(int target, int x, int y);
    void copyTo(int target, int x, int y) const;

private:
    unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
    int width_ = 0, height_ = 0;
};

}  // namespace plimsoll::editor
