// Renders a sequence of surfaces (plain arrays) with one fixed camera and hands the images to a
// FrameSink. The camera frames the first surface's bounds automatically and then stays put, so
// the video does not swim as the tissue deforms or opens.
#pragma once

#include "frame_sink.hpp"
#include "polycut/render/renderer.hpp"

#include <memory>
#include <optional>
#include <span>
#include <string>

namespace polycut::record {

/// Rendering settings of a recording.
struct RecordRender {
    int width = 640; ///< [px]
    int height = 480; ///< [px]
    int msaa = 4; ///< multisample count (0 = off)
    /// Cull back faces: the server's surface (skin + cut faces) is closed and oriented
    /// outwards (protocol.md), so the image is the same and llvmpipe draws half the triangles.
    /// `--two-sided` turns it off for surfaces that are not.
    bool cull_back_faces = true;
    /// Also write every `still_every`-th rendered frame as a PNG here ("" = no stills).
    std::string stills_dir;
    long still_every = 60; ///< [frames], > 0
    /// A fixed camera (e.g. the scene's); nullopt frames the first surface automatically.
    std::optional<render::Camera> camera;
};

/// Renders surfaces to a sink. Not thread-safe (owns a GL context).
class FrameRecorder {
public:
    /// Creates the renderer (InputError for bad settings; polycut::Error if GL fails).
    FrameRecorder(const RecordRender& settings, std::unique_ptr<FrameSink> sink);

    /// Renders one frame (the surface and the rigid tools) and writes it to the sink. The first
    /// call fixes the camera.
    void add(const render::SurfaceArrays& surface, std::span<const render::Tool> tools = {});
    /// Finishes the sink (see FrameSink::finish).
    void finish();

    /// Frames written.
    long frames() const { return m_frames; }
    /// The camera in use (set by the first add()).
    const std::optional<render::Camera>& camera() const { return m_camera; }
    /// The last rendered image.
    const render::Image& last_image() const { return m_image; }
    /// The sink's description.
    std::string describe() const { return m_sink->describe(); }
    /// Total time spent rendering and writing [ms].
    double busy_ms() const { return m_busy_ms; }

private:
    RecordRender m_settings;
    render::Renderer m_renderer;
    std::unique_ptr<FrameSink> m_sink;
    std::optional<render::Camera> m_camera;
    render::Image m_image;
    long m_frames = 0;
    double m_busy_ms = 0;
};

} // namespace polycut::record
