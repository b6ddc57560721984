// The Renderer: turns a DrawList into GL draws on a multisampled FBO, resolves it and reads back
// RGBA8 (render_config.cpp validates settings, shaded_mesh.cpp builds normals).
#include "polycut/render/renderer.hpp"

#include "gl.hpp"
#include "overlay_geometry.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "shaders.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace polycut::render {

namespace {

/// GL names of one framebuffer with a colour and (optionally) a depth renderbuffer.
struct Framebuffer {
    GLuint fbo = 0, colour = 0, depth = 0;

    void create(int width, int height, int samples, bool with_depth) {
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glGenRenderbuffers(1, &colour);
        glBindRenderbuffer(GL_RENDERBUFFER, colour);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
        if (with_depth) {
            glGenRenderbuffers(1, &depth);
            glBindRenderbuffer(GL_RENDERBUFFER, depth);
            glRenderbufferStorageMultisample(
                GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        }
        glBindRenderbuffer(GL_RENDERBUFFER, 0);
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            throw Error("GL",
                "framebuffer incomplete (" + std::to_string(width) + "x" + std::to_string(height)
                    + ", " + std::to_string(samples) + " samples)");
    }

    void destroy() {
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(1, &colour);
        if (depth != 0)
            glDeleteRenderbuffers(1, &depth);
    }
};

void set_matrix(GLuint program, const char* name, const Eigen::Matrix4d& m) {
    const Eigen::Matrix4f f = m.cast<float>(); // column-major, as GL expects
    glProgramUniformMatrix4fv(program, glGetUniformLocation(program, name), 1, GL_FALSE, f.data());
}

/// Copies `bytes` into the buffer bound to `target`, growing it (by half again) only when
/// the data does not fit, so a steady frame loop does not reallocate. The read-back at the
/// end of every frame has already waited for the previous draw, so the copy never stalls.
void upload(GLenum target, std::size_t bytes, const void* data, std::size_t& capacity) {
    if (bytes > capacity) {
        capacity = bytes + bytes / 2;
        glBufferData(target, GLsizeiptr(capacity), nullptr, GL_DYNAMIC_DRAW);
    }
    glBufferSubData(target, 0, GLsizeiptr(bytes), data);
}

void check_finite(const Vec3& v, const std::string& where) {
    if (!v.allFinite())
        throw InputError(where, "not finite");
}

} // namespace

struct Renderer::Impl {
    RenderConfig config;
    std::unique_ptr<GlContext> context;
    bool multisampled = false;
    Framebuffer draw_target, resolve_target;
    GLuint lit_program = 0, line_program = 0;
    GLuint lit_vao = 0, lit_vbo = 0, lit_ebo = 0, line_vao = 0, line_vbo = 0;
    std::size_t lit_vbo_bytes = 0, lit_ebo_bytes = 0, line_vbo_bytes = 0; // buffer capacities

    // Per-frame scratch, kept so that a steady frame loop does not allocate.
    ShadedMesh shaded;
    LitGeometry lit;
    std::vector<LineVertex> lines;
    std::vector<std::uint64_t> edge_keys;
    RenderTimings timings;

    void create_gl_objects();
    void destroy_gl_objects();
    void fill_lit(const DrawList& scene);
    void fill_lines(const DrawList& scene);
    void upload_all();
    void draw(const Camera& camera);
};

void Renderer::Impl::create_gl_objects() {
    GLint max_size = 0, max_samples = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    if (config.width > max_size || config.height > max_size)
        throw InputError(
            "/width", "larger than GL_MAX_RENDERBUFFER_SIZE " + std::to_string(max_size));
    if (config.msaa_samples > max_samples)
        throw InputError("/msaa_samples",
            std::to_string(config.msaa_samples) + " > GL_MAX_SAMPLES "
                + std::to_string(max_samples));

    multisampled = config.msaa_samples > 1;
    draw_target.create(config.width, config.height, multisampled ? config.msaa_samples : 0, true);
    if (multisampled)
        resolve_target.create(config.width, config.height, 0, false);

    lit_program = config.per_pixel_lighting
        ? gl::link_program(shaders::kLitVertex, shaders::kLitFragment)
        : gl::link_program(shaders::kGouraudVertex, shaders::kGouraudFragment);
    line_program = gl::link_program(shaders::kLineVertex, shaders::kLineFragment);

    // Bind-to-edit rather than 4.5 direct state access: libOSMesa exports the GL entry points
    // only up to about 4.1 (glCreate*, glNamed* would need OSMesaGetProcAddress).
    auto attribute = [](GLuint index, GLint size, GLenum type, GLboolean normalized, GLsizei stride,
                         std::size_t offset) {
        glEnableVertexAttribArray(index);
        glVertexAttribPointer(index, size, type, normalized, stride,
            reinterpret_cast<const void*>(offset)); // NOLINT: GL's offset-as-pointer
    };
    glGenVertexArrays(1, &lit_vao);
    glGenBuffers(1, &lit_vbo);
    glGenBuffers(1, &lit_ebo);
    glBindVertexArray(lit_vao);
    glBindBuffer(GL_ARRAY_BUFFER, lit_vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, lit_ebo);
    attribute(0, 3, GL_FLOAT, GL_FALSE, sizeof(LitVertex), offsetof(LitVertex, position));
    attribute(1, 3, GL_FLOAT, GL_FALSE, sizeof(LitVertex), offsetof(LitVertex, normal));
    attribute(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(LitVertex), offsetof(LitVertex, colour));

    glGenVertexArrays(1, &line_vao);
    glGenBuffers(1, &line_vbo);
    glBindVertexArray(line_vao);
    glBindBuffer(GL_ARRAY_BUFFER, line_vbo);
    attribute(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), offsetof(LineVertex, position));
    attribute(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(LineVertex), offsetof(LineVertex, colour));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    // Lights are fixed in camera space (config.light_direction), so set them once.
    Eigen::Vector3f key(config.light_direction.data());
    key.normalize();
    const Eigen::Vector3f fill = Eigen::Vector3f(-key.x(), -key.y(), key.z()).normalized();
    const GLuint p = lit_program;
    glProgramUniform3fv(p, glGetUniformLocation(p, "u_key_direction"), 1, key.data());
    glProgramUniform3fv(p, glGetUniformLocation(p, "u_fill_direction"), 1, fill.data());
    glProgramUniform1f(p, glGetUniformLocation(p, "u_ambient"), config.ambient);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_key"), config.key);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_fill"), config.fill);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_specular"), config.specular);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_shininess"), config.shininess);
    gl::check("renderer set-up");
}

void Renderer::Impl::destroy_gl_objects() {
    glDeleteBuffers(1, &lit_vbo);
    glDeleteBuffers(1, &lit_ebo);
    glDeleteBuffers(1, &line_vbo);
    glDeleteVertexArrays(1, &lit_vao);
    glDeleteVertexArrays(1, &line_vao);
    glDeleteProgram(lit_program);
    glDeleteProgram(line_program);
    draw_target.destroy();
    if (multisampled)
        resolve_target.destroy();
}

void Renderer::Impl::fill_lit(const DrawList& scene) {
    Stopwatch watch;
    build_shaded_mesh(scene.surface, config.crease_angle_deg, shaded);
    timings.normals_ms = watch.ms();
    const std::array<std::array<std::uint8_t, 4>, 3> colours = { to_rgba8(config.interior_colour),
        to_rgba8(config.skin_colour), to_rgba8(config.cut_colour) };
    const std::size_t n = shaded.source.size();
    lit.vertices.resize(n);
    for (std::size_t r = 0; r < n; ++r) {
        LitVertex& v = lit.vertices[r];
        std::copy_n(&shaded.positions[3 * r], 3, v.position);
        std::copy_n(&shaded.normals[3 * r], 3, v.normal);
        std::copy_n(colours[shaded.tags[r]].data(), 4, v.colour);
    }
    lit.indices.assign(shaded.triangles.begin(), shaded.triangles.end());

    const auto tool_colour = to_rgba8(config.tool_colour);
    for (const Tool& tool : scene.tools) {
        // Two-sided lighting makes the winding irrelevant; tools are drawn as they are.
        switch (tool.kind) {
        case Tool::Kind::Sphere:
            append_sphere(tool.position, tool.radius, tool.rotation, tool_colour, lit);
            break;
        case Tool::Kind::Capsule: {
            const Vec3 half = 0.5 * tool.length * tool.rotation.col(2);
            append_capsule(
                tool.position - half, tool.position + half, tool.radius, tool_colour, lit);
            break;
        }
        case Tool::Kind::Box:
            append_box(tool.position, tool.size, tool.rotation, tool_colour, lit);
            break;
        }
    }
    if (!scene.blade && scene.arrows.empty())
        return;
    double radius = config.overlay_radius;
    if (radius == 0) {
        double size = 0;
        if (!scene.surface.positions.empty()) {
            const auto [lo, hi] = bounds(scene.surface.positions);
            size = (hi - lo).norm();
        }
        if (scene.blade)
            size = std::max(size, (scene.blade->b - scene.blade->a).norm());
        radius = size > 0 ? 0.004 * size : 1e-3;
    }
    if (scene.blade)
        append_cylinder(scene.blade->a, scene.blade->b, radius, to_rgba8(config.blade_colour), lit);
    for (const Arrow& arrow : scene.arrows)
        append_arrow(arrow.origin, arrow.vector, radius, to_rgba8(config.arrow_colour), lit);
}

void Renderer::Impl::fill_lines(const DrawList& scene) {
    lines.clear();
    if (!config.wireframe)
        return;
    const auto colour = to_rgba8(config.line_colour);
    auto push = [&](const float* p) {
        LineVertex v {};
        std::copy_n(p, 3, v.position);
        std::copy_n(colour.data(), 4, v.colour);
        lines.push_back(v);
    };
    if (!scene.wire_edges.empty()) {
        for (std::size_t i = 0; i < scene.wire_edges.size(); i += 3)
            push(&scene.wire_edges[i]);
        return;
    }
    // No cell edges given: draw each triangle edge of the surface once.
    const auto& tri = scene.surface.triangles;
    edge_keys.clear();
    for (std::size_t t = 0; t < tri.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = tri[t + k], b = tri[t + (k + 1) % 3];
            edge_keys.push_back(std::min(a, b) << 32 | std::max(a, b));
        }
    std::sort(edge_keys.begin(), edge_keys.end());
    edge_keys.erase(std::unique(edge_keys.begin(), edge_keys.end()), edge_keys.end());
    for (const std::uint64_t key : edge_keys) {
        push(&scene.surface.positions[3 * (key >> 32)]);
        push(&scene.surface.positions[3 * (key & 0xffffffffu)]);
    }
}

void Renderer::Impl::upload_all() {
    if (!lit.indices.empty()) {
        glBindVertexArray(lit_vao);
        glBindBuffer(GL_ARRAY_BUFFER, lit_vbo);
        upload(GL_ARRAY_BUFFER, lit.vertices.size() * sizeof(LitVertex), lit.vertices.data(),
            lit_vbo_bytes);
        upload(GL_ELEMENT_ARRAY_BUFFER, lit.indices.size() * sizeof(std::uint32_t),
            lit.indices.data(), lit_ebo_bytes);
    }
    if (!lines.empty()) {
        glBindVertexArray(line_vao);
        glBindBuffer(GL_ARRAY_BUFFER, line_vbo);
        upload(GL_ARRAY_BUFFER, lines.size() * sizeof(LineVertex), lines.data(), line_vbo_bytes);
    }
    glBindVertexArray(0);
}

void Renderer::Impl::draw(const Camera& camera) {
    Stopwatch watch;
    const Eigen::Matrix4d view = camera.view_matrix();
    const Eigen::Matrix4d projection
        = camera.projection_matrix(double(config.width) / double(config.height));

    glBindFramebuffer(GL_FRAMEBUFFER, draw_target.fbo);
    glViewport(0, 0, config.width, config.height);
    glClearColor(config.background[0], config.background[1], config.background[2], 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (config.cull_back_faces) {
        glEnable(GL_CULL_FACE); // closed oriented surfaces: back faces are hidden anyway
        glCullFace(GL_BACK);
    } else {
        glDisable(GL_CULL_FACE); // two-sided lighting; cut faces may face either way
    }
    if (multisampled)
        glEnable(GL_MULTISAMPLE);

    if (!lit.indices.empty()) {
        // Push filled faces back a little so the wireframe drawn on them wins the depth test.
        if (config.wireframe) {
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(1.0f, 1.0f);
        } else {
            glDisable(GL_POLYGON_OFFSET_FILL);
        }
        glBindVertexArray(lit_vao);
        set_matrix(lit_program, "u_view", view);
        set_matrix(lit_program, "u_projection", projection);
        glUseProgram(lit_program);
        glDrawElements(GL_TRIANGLES, GLsizei(lit.indices.size()), GL_UNSIGNED_INT, nullptr);
    }
    if (!lines.empty()) {
        glBindVertexArray(line_vao);
        set_matrix(line_program, "u_view", view);
        set_matrix(line_program, "u_projection", projection);
        glUseProgram(line_program);
        glLineWidth(config.line_width);
        glDrawArrays(GL_LINES, 0, GLsizei(lines.size()));
    }
    glBindVertexArray(0);
    timings.submit_ms = watch.ms();

    if (config.profile) {
        watch.restart();
        glFinish();
        timings.raster_ms = watch.ms();
    }
    watch.restart();
    if (multisampled) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_target.fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_target.fbo);
        glBlitFramebuffer(0, 0, config.width, config.height, 0, 0, config.width, config.height,
            GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_target.fbo);
    } else {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_target.fbo);
    }
    if (config.profile) {
        glFinish();
        timings.resolve_ms = watch.ms();
    }
    gl::check("draw");
}

Renderer::Renderer(RenderConfig config, std::unique_ptr<GlContext> context)
    : m_impl(std::make_unique<Impl>()) {
    config.validate();
    m_impl->config = config;
    m_impl->context = context ? std::move(context) : make_osmesa_context(1, 1);
    m_impl->context->make_current();
    m_impl->create_gl_objects();
}

Renderer::~Renderer() {
    if (m_impl) {
        m_impl->context->make_current();
        m_impl->destroy_gl_objects();
    }
}

Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::render(const DrawList& scene, const Camera& camera, Image& out) {
    Impl& impl = *m_impl;
    impl.timings = {};
    const Stopwatch total;
    Stopwatch watch;
    scene.surface.validate();
    camera.validate();
    if (scene.wire_edges.size() % 6 != 0)
        throw InputError("/wire_edges", "size is not a multiple of 6 (two points per edge)");
    for (std::size_t i = 0; i < scene.wire_edges.size(); ++i)
        if (!std::isfinite(scene.wire_edges[i]))
            throw InputError("/wire_edges/" + std::to_string(i / 6), "not finite");
    if (scene.blade) {
        check_finite(scene.blade->a, "/blade/a");
        check_finite(scene.blade->b, "/blade/b");
    }
    for (std::size_t i = 0; i < scene.arrows.size(); ++i) {
        check_finite(scene.arrows[i].origin, "/arrows/" + std::to_string(i) + "/origin");
        check_finite(scene.arrows[i].vector, "/arrows/" + std::to_string(i) + "/vector");
    }
    for (std::size_t i = 0; i < scene.tools.size(); ++i) {
        const Tool& t = scene.tools[i];
        const std::string at = "/tools/" + std::to_string(i);
        check_finite(t.position, at + "/position");
        if (!t.rotation.allFinite() || !std::isfinite(t.radius) || !std::isfinite(t.length)
            || !t.size.allFinite())
            throw InputError(at, "not finite");
    }

    impl.timings.validate_ms = watch.ms();
    impl.context->make_current();
    watch.restart();
    impl.fill_lit(scene);
    impl.fill_lines(scene);
    impl.timings.fill_ms = watch.ms() - impl.timings.normals_ms;
    watch.restart();
    impl.upload_all();
    impl.timings.upload_ms = watch.ms();
    impl.draw(camera);
    watch.restart();
    impl.context->read_pixels(impl.config.width, impl.config.height, out);
    impl.timings.read_ms = watch.ms();
    impl.timings.total_ms = total.ms();
}

const RenderTimings& Renderer::timings() const {
    return m_impl->timings;
}

Image Renderer::render(const DrawList& scene, const Camera& camera) {
    Image image;
    render(scene, camera, image);
    return image;
}

const RenderConfig& Renderer::config() const {
    return m_impl->config;
}

std::string Renderer::description() const {
    return m_impl->context->description();
}

std::pair<Vec3, Vec3> bounds(std::span<const float> positions) {
    if (positions.size() < 3 || positions.size() % 3 != 0)
        throw InputError("bounds", "needs at least one point (#V x 3)");
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    for (std::size_t i = 0; i < positions.size(); i += 3)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], double(positions[i + c]));
            hi[c] = std::max(hi[c], double(positions[i + c]));
        }
    return { lo, hi };
}

} // namespace polycut::render
