// The off-screen OpenGL context the renderer draws into, behind a small interface so the backend
// can be swapped. Today: OSMesa (GL 4.5 core on llvmpipe). Mesa 25.1 removes OSMesa; the planned
// replacement is an EGL surfaceless context (EGL_MESA_platform_surfaceless + eglBindAPI(GL) +
// a core-profile context with no surface). The renderer only needs what this interface offers,
// and it draws into its own framebuffer objects, so a new backend is one new class here.
#pragma once

#include "polycut/render/image.hpp"

#include <memory>
#include <string>

namespace polycut::render {

/// An OpenGL >= 4.5 core-profile context that can be made current on the calling thread.
/// Not thread-safe: use one context per thread, or serialize calls.
class GlContext {
public:
    virtual ~GlContext() = default;
    GlContext() = default;
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    /// Makes this context current on the calling thread (cheap if it already is).
    virtual void make_current() = 0;
    /// Size of the context's default drawable [px]; the renderer uses its own FBOs of any size.
    virtual int width() const = 0;
    /// Size of the context's default drawable [px].
    virtual int height() const = 0;
    /// GL_VERSION and GL_RENDERER, e.g. "4.5 (Core Profile) Mesa 22.3.6 / llvmpipe (...)".
    virtual std::string description() const = 0;
    /// Reads the framebuffer bound to GL_READ_FRAMEBUFFER, region (0, 0, width, height) [px],
    /// as RGBA8 into `out`, top row first (GL rows are bottom-up; this flips them). Resizes `out`.
    /// The context must be current.
    virtual void read_pixels(int width, int height, Image& out) = 0;
};

/// Creates an OSMesa core-profile context (GL 4.5) with a width x height RGBA drawable [px].
/// Throws InputError for a size outside [1, 16384], and polycut::Error if OSMesa cannot create
/// a 4.5 core context.
std::unique_ptr<GlContext> make_osmesa_context(int width = 1, int height = 1);

} // namespace polycut::render
