// The off-screen renderer: shaded tissue (skin and cut surfaces in different colours), optional
// wireframe of simulation cells, scalpel blade and force arrows, 4x MSAA, RGBA8 output.
#pragma once

#include "polycut/render/camera.hpp"
#include "polycut/render/gl_context.hpp"
#include "polycut/render/image.hpp"
#include "polycut/render/shaded_mesh.hpp"

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace polycut::render {

/// A colour, each channel in [0, 1] (written to the image as-is, no gamma conversion).
using Rgb = std::array<float, 3>;

/// Fixed settings of a Renderer.
struct RenderConfig {
    int width = 640; ///< image width [px], 1..8192
    int height = 480; ///< image height [px], 1..8192
    int msaa_samples = 4; ///< multisample count; 0 or 1 = no multisampling
    Rgb background { 0.11f, 0.12f, 0.15f };
    Rgb skin_colour { 0.91f, 0.68f, 0.62f }; ///< pinkish skin
    Rgb cut_colour { 0.66f, 0.07f, 0.09f }; ///< fresh cut tissue, deep red
    Rgb interior_colour { 0.85f, 0.78f, 0.45f }; ///< interior faces (normally not drawn)
    Rgb line_colour { 0.15f, 0.17f, 0.20f }; ///< wireframe
    Rgb blade_colour { 0.78f, 0.80f, 0.84f }; ///< scalpel, steel
    Rgb arrow_colour { 0.20f, 0.62f, 0.95f }; ///< force arrows
    Rgb tool_colour { 0.55f, 0.60f, 0.68f }; ///< rigid tools (probe, spatula, blade), steel
    /// Key light direction towards the light, in camera space (x right, y up, z towards the
    /// viewer): (0, 0, 1) is a pure headlight. A weaker fill light comes from the mirrored side.
    std::array<float, 3> light_direction { 0.3f, 0.45f, 1.0f };
    float ambient = 0.18f; ///< ambient intensity
    float key = 0.80f; ///< key light intensity
    float fill = 0.25f; ///< fill light intensity
    float specular = 0.18f; ///< Blinn-Phong specular intensity (wet tissue sheen), 0 = matte
    float shininess = 48.0f; ///< Blinn-Phong exponent
    /// Lighting per pixel (Phong) instead of per vertex (Gouraud). Per pixel is sharper on
    /// coarse meshes but costs ~1/3 more per frame on llvmpipe with 4x MSAA.
    bool per_pixel_lighting = false;
    double crease_angle_deg = 35; ///< see build_shaded_mesh: 0 = flat, 180 = smooth
    bool wireframe = false; ///< draw DrawList::wire_edges, or the triangle edges if none
    float line_width = 1.0f; ///< wireframe width [px]
    float overlay_radius = 0; ///< blade / arrow shaft radius [m]; 0 = 0.4 % of the surface size
    /// Skip triangles facing away from the camera. Valid for closed, consistently oriented
    /// surfaces seen from outside (the simulation's skin + cut surface is one, issue 5 item 6):
    /// their back faces are always hidden, so the image is the same and llvmpipe sets up and
    /// rasterizes about half the triangles. Leave off for open or inconsistently oriented input.
    bool cull_back_faces = false;
    /// Wait for the GL after each phase so that Renderer::timings() splits the frame into
    /// rasterization, resolve and read-back (costs a little; off for production use).
    bool profile = false;

    /// Throws InputError naming the field ("/width", ...) if a setting is out of range.
    void validate() const;
};

/// A scalpel blade: the cutting edge as a segment [m].
struct Blade {
    Vec3 a; ///< one end [m]
    Vec3 b; ///< other end [m]
};

/// A force arrow drawn from `origin` to `origin + vector` (scale forces [N] to [m] beforehand).
struct Arrow {
    Vec3 origin; ///< [m]
    Vec3 vector; ///< [m]
};

/// A rigid tool (issue 15: probe tip, shaft, blade): a shape in its own frame, put in the world
/// by `position` and `rotation` (columns: the tool frame's axes in the world).
struct Tool {
    enum class Kind {
        Sphere, ///< ball of `radius` about the origin
        Capsule, ///< `length` along local z centred at the origin, `radius` around it
        Box, ///< edge lengths `size` [m] along local x, y, z, centred at the origin
    };
    Kind kind = Kind::Sphere;
    Vec3 position = Vec3::Zero(); ///< [m]
    Mat3 rotation = Mat3::Identity();
    double radius = 0; ///< Sphere, Capsule [m]
    double length = 0; ///< Capsule [m]
    Vec3 size = Vec3::Zero(); ///< Box [m]
};

/// Everything drawn in one frame, as non-owning views.
struct DrawList {
    SurfaceArrays surface; ///< the tissue surface
    std::span<const float> wire_edges; ///< (#E x 2 x 3) [m] segment end points, e.g. cell edges
    std::optional<Blade> blade; ///< scalpel, if any
    std::span<const Arrow> arrows; ///< force arrows
    std::span<const Tool> tools; ///< rigid tools
};

/// Wall time of the phases of the last Renderer::render call [ms]. Without
/// RenderConfig::profile, GL work is only waited for at the read-back, so `raster_ms` and
/// `resolve_ms` are 0 and `read_ms` includes them.
struct RenderTimings {
    double validate_ms = 0; ///< input checks
    double normals_ms = 0; ///< build_shaded_mesh (shading normals)
    double fill_ms = 0; ///< interleaved vertex arrays, overlays, wireframe edges
    double upload_ms = 0; ///< buffer uploads
    double submit_ms = 0; ///< clear and draw calls (llvmpipe: vertex shading and binning)
    double raster_ms = 0; ///< profile only: waiting for rasterization (glFinish)
    double resolve_ms = 0; ///< profile only: MSAA resolve blit
    double read_ms = 0; ///< glReadPixels and the row flip
    double total_ms = 0; ///< the whole call
};

/// Draws DrawLists into RGBA images off screen. Owns a GL context (OSMesa by default) and its GL
/// objects; every call makes the context current first. Not thread-safe.
/// Rendering is deterministic: the same input gives the same bytes.
class Renderer {
public:
    /// Validates `config` (InputError) and creates the GL objects; creates an OSMesa context if
    /// `context` is null. Throws polycut::Error if the GL setup fails.
    explicit Renderer(RenderConfig config = {}, std::unique_ptr<GlContext> context = nullptr);
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    /// Renders `scene` seen by `camera` into `out` (resized to width x height). Throws
    /// InputError for bad input (see SurfaceArrays::validate, Camera::validate, non-finite
    /// overlays or wire_edges not a multiple of 6). After warm-up, allocates only when the
    /// scene grows.
    void render(const DrawList& scene, const Camera& camera, Image& out);
    /// As above, returning a new image.
    Image render(const DrawList& scene, const Camera& camera);

    /// Phase timings of the last render() call.
    const RenderTimings& timings() const;
    /// The configuration in use.
    const RenderConfig& config() const;
    /// The GL context's description (version and renderer).
    std::string description() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Axis-aligned bounds (lo, hi) of positions (#V x 3) [m]; throws InputError if empty.
std::pair<Vec3, Vec3> bounds(std::span<const float> positions);

} // namespace polycut::render
