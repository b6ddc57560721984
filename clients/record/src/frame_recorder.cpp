// Fixed-camera surface rendering into a frame sink (see frame_recorder.hpp).
#include "frame_recorder.hpp"

#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"

#include <filesystem>

namespace polycut::record {

namespace {

render::RenderConfig render_config(const RecordRender& settings) {
    render::RenderConfig config;
    config.width = settings.width;
    config.height = settings.height;
    config.msaa_samples = settings.msaa;
    config.cull_back_faces = settings.cull_back_faces;
    return config;
}

} // namespace

FrameRecorder::FrameRecorder(const RecordRender& settings, std::unique_ptr<FrameSink> sink)
    : m_settings(settings)
    , m_renderer(render_config(settings))
    , m_sink(std::move(sink))
    , m_camera(settings.camera) {
    if (m_camera) {
        m_camera->validate();
    }
    if (m_settings.still_every <= 0) {
        throw InputError("--still-every", "must be > 0");
    }
    if (!m_settings.stills_dir.empty()) {
        std::error_code error;
        std::filesystem::create_directories(m_settings.stills_dir, error);
        if (error) {
            throw FileError(m_settings.stills_dir, 0, "cannot create: " + error.message());
        }
    }
}

void FrameRecorder::add(const render::SurfaceArrays& surface, std::span<const render::Tool> tools) {
    const Stopwatch watch;
    if (!m_camera) {
        const auto [lo, hi] = render::bounds(surface.positions);
        m_camera = render::frame(lo, hi, double(m_settings.width) / double(m_settings.height));
    }
    render::DrawList scene;
    scene.surface = surface;
    scene.tools = tools;
    m_renderer.render(scene, *m_camera, m_image);
    m_sink->write(m_frames, m_image);
    if (!m_settings.stills_dir.empty() && m_frames % m_settings.still_every == 0) {
        render::write_png(
            (std::filesystem::path(m_settings.stills_dir) / png_frame_name(m_frames)).string(),
            m_image);
    }
    ++m_frames;
    m_busy_ms += watch.ms();
}

void FrameRecorder::finish() {
    m_sink->finish();
}

} // namespace polycut::record
