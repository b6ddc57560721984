// Golden-image tests: fixed procedural scenes rendered and compared with tests/golden/*.png under
// a per-pixel tolerance and a bounded share of differing pixels (llvmpipe is deterministic run
// to run, but other Mesa versions or backends may differ by a few levels at edges).
// Regenerate the goldens with: POLYCUT_UPDATE_GOLDEN=1 ./test_render --gtest_filter='Golden*'
#include "polycut/render/renderer.hpp"
#include "scenes.hpp"

#include <cstdlib>
#include <filesystem>
#include <gtest/gtest.h>

namespace polycut::render::test {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr int kTolerance = 8; // max channel difference of a matching pixel
constexpr double kMaxDifferingShare = 0.005; // at most 0.5 % of pixels may differ

RenderConfig golden_config() {
    RenderConfig config;
    config.width = kWidth;
    config.height = kHeight;
    return config;
}

/// Renders `surface` and compares it with tests/golden/<name>.png (or rewrites the golden).
void check_golden(const std::string& name, const DrawList& scene, const RenderConfig& config) {
    Renderer renderer(config);
    const Image image = renderer.render(scene, block_camera(config.width, config.height));
    const std::filesystem::path golden
        = std::filesystem::path(POLYCUT_SOURCE_DIR) / "tests" / "golden" / (name + ".png");
    const char* update = std::getenv("POLYCUT_UPDATE_GOLDEN");
    if (update != nullptr && std::string(update) == "1") {
        write_png(golden.string(), image);
        GTEST_SKIP() << "wrote " << golden;
    }
    ASSERT_TRUE(std::filesystem::exists(golden))
        << golden << " is missing; run with POLYCUT_UPDATE_GOLDEN=1 to create it";
    const Image expected = read_png(golden.string());
    ASSERT_EQ(expected.width, image.width);
    ASSERT_EQ(expected.height, image.height);
    const ImageDiff diff = compare(image, expected, kTolerance);
    if (diff.differing_fraction > kMaxDifferingShare) {
        const std::filesystem::path out = std::filesystem::path(POLYCUT_BINARY_DIR) / "golden";
        std::filesystem::create_directories(out);
        write_png((out / (name + ".actual.png")).string(), image);
        write_png(
            (out / (name + ".diff.png")).string(), difference_image(image, expected, kTolerance));
        ADD_FAILURE() << "actual and diff images written to " << out;
    }
    EXPECT_LE(diff.differing_fraction, kMaxDifferingShare)
        << name << ": " << diff.differing_pixels << " pixels differ by more than " << kTolerance
        << " (max channel difference " << diff.max_channel_diff << ")";
}

TEST(Golden, UncutBlock) {
    const TestSurface block = make_block();
    check_golden("block_uncut", block.draw_list(), golden_config());
}

TEST(Golden, NotchedBlock) {
    BlockSpec spec;
    spec.notch_depth = 0.02;
    const TestSurface block = make_block(spec);
    check_golden("block_notch", block.draw_list(), golden_config());
}

TEST(Golden, OpenedNotch) {
    BlockSpec spec;
    spec.notch_depth = 0.02;
    spec.opening = 0.012;
    const TestSurface block = make_block(spec);
    check_golden("block_notch_open", block.draw_list(), golden_config());
}

TEST(Golden, WireframeBladeAndArrow) {
    BlockSpec spec;
    spec.notch_depth = 0.02;
    const TestSurface block = make_block(spec);
    RenderConfig config = golden_config();
    config.wireframe = true;
    DrawList scene = block.draw_list();
    scene.blade = Blade { Vec3(0.048, -0.01, 0.05), Vec3(0.048, 0.03, 0.025) };
    const Arrow arrow { Vec3(0.09, 0.03, 0.04), Vec3(0.0, 0.0, 0.03) };
    scene.arrows = std::span(&arrow, 1);
    check_golden("block_overlays", scene, config);
}

} // namespace
} // namespace polycut::render::test
