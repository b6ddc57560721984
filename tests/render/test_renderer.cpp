// Renderer behaviour: determinism, orientation of the output, cut colour only after a cut,
// framing, overlays, MSAA and clear errors for bad input.
#include "polycut/common/error.hpp"
#include "polycut/render/renderer.hpp"
#include "scenes.hpp"

#include <gtest/gtest.h>

namespace polycut::render::test {
namespace {

RenderConfig small_config(int width = 160, int height = 120) {
    RenderConfig config;
    config.width = width;
    config.height = height;
    return config;
}

/// True if pixel (x, y) differs from the background colour by more than 3 levels.
bool is_object(const Image& image, const RenderConfig& config, int x, int y) {
    const std::uint8_t* p = image.pixel(x, y);
    for (int c = 0; c < 3; ++c)
        if (std::abs(int(p[c]) - int(std::lround(config.background[c] * 255))) > 3)
            return true;
    return false;
}

/// Bounding box (x0, y0, x1, y1) of non-background pixels and their count.
struct Coverage {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
    long count = 0;
};

Coverage coverage(const Image& image, const RenderConfig& config) {
    Coverage c;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (is_object(image, config, x, y)) {
                c.x0 = std::min(c.x0, x), c.x1 = std::max(c.x1, x);
                c.y0 = std::min(c.y0, y), c.y1 = std::max(c.y1, y);
                ++c.count;
            }
    return c;
}

TEST(Renderer, ContextIsGl45Core) {
    const Renderer renderer(small_config());
    EXPECT_NE(renderer.description().find("4.5"), std::string::npos) << renderer.description();
}

TEST(Renderer, SameInputGivesIdenticalBytes) {
    BlockSpec spec;
    spec.notch_depth = 0.02;
    spec.opening = 0.01;
    const TestSurface block = make_block(spec);
    const RenderConfig config = small_config();
    const Camera camera = block_camera(config.width, config.height);
    Renderer renderer(config);
    const Image first = renderer.render(block.draw_list(), camera);
    const Image again = renderer.render(block.draw_list(), camera);
    Renderer fresh(config);
    const Image other = fresh.render(block.draw_list(), camera);
    EXPECT_EQ(first.rgba, again.rgba);
    EXPECT_EQ(first.rgba, other.rgba);
}

TEST(Renderer, FramesDoNotLeakIntoEachOther) {
    // Buffers are reused and grown between frames: a small scene after a large one must look
    // exactly as it does from a fresh renderer.
    const TestSurface block = make_block();
    const TestSurface blob = make_blob(96, 48, 0.05);
    const RenderConfig config = small_config();
    const Camera camera = block_camera(config.width, config.height);
    Renderer renderer(config);
    renderer.render(blob.draw_list(), camera);
    const Image after_large = renderer.render(block.draw_list(), camera);
    renderer.render(DrawList {}, camera);
    const Image after_empty = renderer.render(block.draw_list(), camera);
    const Image fresh = Renderer(config).render(block.draw_list(), camera);
    EXPECT_EQ(after_large.rgba, fresh.rgba);
    EXPECT_EQ(after_empty.rgba, fresh.rgba);
}

TEST(Renderer, ImageIsRightWayUp) {
    // One triangle above and to the right of the target: it must land in the top-right
    // quadrant of the image (GL's bottom-up rows are flipped).
    TestSurface s;
    s.positions = { 0.2f, 0, 0.2f, 0.4f, 0, 0.2f, 0.3f, 0, 0.4f };
    s.triangles = { 0, 1, 2 };
    s.tags = { 1 };
    Camera camera;
    camera.position = Vec3(0, -2, 0); // looking along +y, z up, x to the right
    camera.target = Vec3(0, 0, 0);
    const RenderConfig config = small_config(100, 100);
    Renderer renderer(config);
    const Coverage c = coverage(renderer.render(s.draw_list(), camera), config);
    ASSERT_GT(c.count, 0);
    EXPECT_GT(c.x0, 50);
    EXPECT_LT(c.y1, 50);
}

TEST(Renderer, CutColourAppearsOnlyAfterTheCut) {
    const RenderConfig config = small_config(320, 240);
    const Camera camera = block_camera(config.width, config.height);
    Renderer renderer(config);
    BlockSpec spec;
    const long before = count_cut_coloured(renderer.render(make_block(spec).draw_list(), camera));
    spec.notch_depth = 0.02;
    const long after = count_cut_coloured(renderer.render(make_block(spec).draw_list(), camera));
    spec.opening = 0.012;
    const long opened = count_cut_coloured(renderer.render(make_block(spec).draw_list(), camera));
    const long pixels = long(config.width) * config.height;
    EXPECT_EQ(before, 0);
    EXPECT_GT(after, pixels / 50); // the notch face covers several % of the image
    EXPECT_GT(opened, pixels / 50);
}

TEST(Renderer, AutomaticCameraFramesTheObject) {
    // frame() sees only the bounding box, so a round blob fills less of the view than a
    // block: at least 40 % of the image width or height and 10 % of its pixels.
    const TestSurface blob = make_blob(48, 24, 0.03);
    const TestSurface block = make_block();
    for (const TestSurface* surface : { &blob, &block })
        for (const auto& [w, h] : { std::pair { 320, 240 }, { 200, 300 } }) {
            const RenderConfig config = small_config(w, h);
            const auto [lo, hi] = bounds(surface->positions);
            const Camera camera = frame(lo, hi, double(w) / h);
            Renderer renderer(config);
            const Coverage c = coverage(renderer.render(surface->draw_list(), camera), config);
            // Inside the image with a border, and not a speck.
            EXPECT_GT(c.x0, 0);
            EXPECT_GT(c.y0, 0);
            EXPECT_LT(c.x1, w - 1);
            EXPECT_LT(c.y1, h - 1);
            EXPECT_GT(c.count, long(w) * h / 10);
            EXPECT_GT(std::max(double(c.x1 - c.x0) / w, double(c.y1 - c.y0) / h), 0.4);
        }
}

TEST(Renderer, PerPixelAndPerVertexLightingAgreeOnFlatFaces) {
    // The block's faces are planar, so both lighting variants see the same normals; they
    // differ only where view-dependent terms vary across a triangle.
    BlockSpec spec;
    spec.notch_depth = 0.02;
    const TestSurface block = make_block(spec);
    RenderConfig config = small_config(320, 240);
    const Camera camera = block_camera(config.width, config.height);
    const Image gouraud = Renderer(config).render(block.draw_list(), camera);
    config.per_pixel_lighting = true;
    const Image phong = Renderer(config).render(block.draw_list(), camera);
    const ImageDiff diff = compare(gouraud, phong, 8);
    EXPECT_LT(diff.differing_fraction, 0.01);
}

TEST(Renderer, EmptySceneIsBackground) {
    const RenderConfig config = small_config(64, 48);
    Renderer renderer(config);
    const Image image = renderer.render(DrawList {}, Camera {});
    EXPECT_EQ(coverage(image, config).count, 0);
    EXPECT_EQ(image.pixel(0, 0)[3], 255);
}

/// Pixels within 12 levels of `colour`.
long count_near(const Image& image, const Rgb& colour) {
    long count = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            bool near = true;
            for (int c = 0; c < 3; ++c)
                near = near && std::abs(image.pixel(x, y)[c] - colour[c] * 255) <= 12;
            count += near;
        }
    return count;
}

TEST(Renderer, WireframeDrawsLineColour) {
    const TestSurface block = make_block();
    RenderConfig config = small_config(320, 240);
    config.line_colour = { 0.0f, 1.0f, 0.0f }; // a colour the shading never produces
    const Camera camera = block_camera(config.width, config.height);
    Renderer plain(config);
    EXPECT_EQ(count_near(plain.render(block.draw_list(), camera), config.line_colour), 0);
    config.wireframe = true;
    Renderer wired(config);
    EXPECT_GT(count_near(wired.render(block.draw_list(), camera), config.line_colour), 1000);
}

TEST(Renderer, ArrowAndBladeAreDrawn) {
    const TestSurface block = make_block();
    RenderConfig config = small_config(320, 240);
    config.arrow_colour = { 0.0f, 0.0f, 1.0f };
    config.blade_colour = { 0.0f, 1.0f, 0.0f };
    config.ambient = 1.0f; // unlit colours, so they can be counted
    config.key = config.fill = config.specular = 0.0f;
    const Camera camera = block_camera(config.width, config.height);
    Renderer renderer(config);
    DrawList scene = block.draw_list();
    const Arrow arrow { Vec3(0.05, 0.03, 0.04), Vec3(0, 0, 0.03) };
    scene.arrows = std::span(&arrow, 1);
    scene.blade = Blade { Vec3(0.02, 0.0, 0.05), Vec3(0.08, 0.0, 0.05) };
    const Image image = renderer.render(scene, camera);
    EXPECT_GT(count_near(image, config.arrow_colour), 20);
    EXPECT_GT(count_near(image, config.blade_colour), 20);
}

TEST(Renderer, ToolsAreDrawnOutwardAtTheirPose) {
    // A probe ball, a capsule shaft and a spatula box beside the block, unlit in the tool
    // colour, with back faces culled (as the recorder renders): each shape covers about its
    // projected area (so none is inside-out), and where the tool's position projects, the
    // pixel is the tool's.
    const TestSurface block = make_block();
    RenderConfig config = small_config(320, 240);
    config.tool_colour = { 0.0f, 1.0f, 0.0f };
    config.ambient = 1.0f;
    config.key = config.fill = config.specular = 0.0f;
    config.cull_back_faces = true;
    const Camera camera = block_camera(config.width, config.height);
    Renderer renderer(config);
    DrawList scene = block.draw_list();
    EXPECT_EQ(count_near(renderer.render(scene, camera), config.tool_colour), 0);
    std::array<Tool, 3> tools;
    tools[0].kind = Tool::Kind::Sphere;
    tools[0].position = Vec3(0.05, 0.03, 0.06);
    tools[0].radius = 0.006;
    tools[1].kind = Tool::Kind::Capsule;
    tools[1].position = Vec3(0.02, 0.0, 0.07);
    tools[1].radius = 0.003;
    tools[1].length = 0.03;
    tools[1].rotation = Eigen::AngleAxisd(0.5, Vec3::UnitX()).toRotationMatrix();
    tools[2].kind = Tool::Kind::Box;
    tools[2].position = Vec3(0.08, 0.0, 0.07);
    tools[2].size = Vec3(0.02, 0.01, 0.002);
    tools[2].rotation = Eigen::AngleAxisd(0.7, Vec3::UnitZ()).toRotationMatrix();
    for (std::size_t i = 0; i < tools.size(); ++i) {
        scene.tools = std::span(&tools[i], 1);
        const Image image = renderer.render(scene, camera);
        EXPECT_GT(count_near(image, config.tool_colour), 30) << i;
        const Vec3 p = camera.project(tools[i].position, config.width, config.height);
        const std::uint8_t* px = image.pixel(int(p.x()), int(p.y()));
        EXPECT_GT(px[1], 230) << i;
        EXPECT_LT(px[0], 25) << i;
    }
    // The ball's silhouette: a disc of the projected radius (within 15 %).
    scene.tools = std::span(&tools[0], 1);
    const Image ball = renderer.render(scene, camera);
    const Vec3 c = camera.project(tools[0].position, config.width, config.height);
    const Vec3 right = camera.view_matrix().block<1, 3>(0, 0).transpose(); // camera x in the world
    const Vec3 rim = camera.project(tools[0].position + 0.006 * right, config.width, config.height);
    const double r = (rim - c).head<2>().norm();
    const double expected = 3.14159265358979 * r * r;
    EXPECT_NEAR(double(count_near(ball, config.tool_colour)), expected, 0.15 * expected);
    Tool bad = tools[0];
    bad.position.x() = std::nan("");
    scene.tools = std::span(&bad, 1);
    EXPECT_THROW(renderer.render(scene, camera), InputError);
}

TEST(Renderer, MultisamplingBlendsEdges) {
    // Without MSAA every pixel is background or a shaded surface colour; with 4x MSAA the
    // silhouette has pixels partly covered, so more distinct colours appear.
    const TestSurface block = make_block();
    auto distinct_colours = [&](int samples) {
        RenderConfig config = small_config(160, 120);
        config.msaa_samples = samples;
        config.ambient = 1.0f;
        config.key = config.fill = config.specular = 0.0f; // flat colour: skin or background
        Renderer renderer(config);
        const Image image
            = renderer.render(block.draw_list(), block_camera(config.width, config.height));
        std::vector<std::uint32_t> colours;
        for (std::size_t i = 0; i < image.rgba.size(); i += 4)
            colours.push_back(image.rgba[i] << 16 | image.rgba[i + 1] << 8 | image.rgba[i + 2]);
        std::sort(colours.begin(), colours.end());
        return std::unique(colours.begin(), colours.end()) - colours.begin();
    };
    EXPECT_EQ(distinct_colours(0), 2);
    EXPECT_GE(distinct_colours(4), 4); // 0/4 .. 4/4 coverage
}

TEST(Renderer, BadInputThrowsInputError) {
    RenderConfig config = small_config();
    config.width = 0;
    EXPECT_THROW(Renderer { config }, InputError);
    config.width = 100000;
    EXPECT_THROW(Renderer { config }, InputError);
    config = small_config();
    config.msaa_samples = 64;
    EXPECT_THROW(Renderer { config }, InputError);
    config = small_config();
    config.cut_colour = { 2.0f, 0.0f, 0.0f };
    EXPECT_THROW(Renderer { config }, InputError);
    EXPECT_THROW(make_osmesa_context(0, 10), InputError);

    Renderer renderer(small_config());
    const Camera camera = block_camera(160, 120);
    TestSurface block = make_block();
    TestSurface bad = block;
    bad.triangles[5] = std::uint32_t(bad.positions.size() / 3);
    EXPECT_THROW(renderer.render(bad.draw_list(), camera), InputError);
    bad = block;
    bad.positions[4] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(renderer.render(bad.draw_list(), camera), InputError);
    Camera degenerate = camera;
    degenerate.target = degenerate.position;
    EXPECT_THROW(renderer.render(block.draw_list(), degenerate), InputError);
    DrawList scene = block.draw_list();
    const std::vector<float> ragged(5, 0.0f);
    scene.wire_edges = ragged;
    EXPECT_THROW(renderer.render(scene, camera), InputError);
    scene = block.draw_list();
    const Arrow nan_arrow { Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0) };
    scene.arrows = std::span(&nan_arrow, 1);
    EXPECT_THROW(renderer.render(scene, camera), InputError);
    // The renderer still works after rejecting input.
    EXPECT_GT(coverage(renderer.render(block.draw_list(), camera), renderer.config()).count, 0);
}

} // namespace
} // namespace polycut::render::test
