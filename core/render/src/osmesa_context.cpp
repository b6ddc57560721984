// The OSMesa backend of GlContext: a GL 4.5 core-profile context on Mesa's llvmpipe.
#include "gl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/render/gl_context.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace polycut::render {

namespace {

class OsMesaContext final : public GlContext {
public:
    OsMesaContext(int width, int height)
        : m_width(width)
        , m_height(height)
        , m_buffer(static_cast<std::size_t>(width) * height * 4) {
        const int attributes[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
            OSMESA_STENCIL_BITS, 0, OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
            OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0 };
        m_context = OSMesaCreateContextAttribs(attributes, nullptr);
        if (m_context == nullptr)
            throw Error("OSMesa", "cannot create a GL 4.5 core-profile context");
        make_current();
    }

    ~OsMesaContext() override {
        if (OSMesaGetCurrentContext() == m_context)
            OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
        OSMesaDestroyContext(m_context);
    }

    void make_current() override {
        if (OSMesaGetCurrentContext() == m_context)
            return;
        if (!OSMesaMakeCurrent(m_context, m_buffer.data(), GL_UNSIGNED_BYTE, m_width, m_height))
            throw Error("OSMesa", "OSMesaMakeCurrent failed");
    }

    int width() const override { return m_width; }
    int height() const override { return m_height; }

    std::string description() const override {
        const_cast<OsMesaContext*>(this)->make_current();
        const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
        const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        return std::string(version ? version : "?") + " / " + (renderer ? renderer : "?");
    }

    void read_pixels(int width, int height, Image& out) override {
        make_current();
        out.width = width;
        out.height = height;
        const std::size_t row = static_cast<std::size_t>(width) * 4;
        out.rgba.resize(row * height);
        m_rows.resize(out.rgba.size());
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, m_rows.data());
        gl::check("glReadPixels");
        // GL row 0 is the bottom of the image.
        for (int y = 0; y < height; ++y)
            std::copy_n(m_rows.data() + row * (height - 1 - y), row, out.rgba.data() + row * y);
    }

private:
    int m_width;
    int m_height;
    std::vector<unsigned char> m_buffer; // the default drawable (unused by the renderer)
    std::vector<unsigned char> m_rows; // bottom-up read-back scratch
    OSMesaContext m_context = nullptr;
};

} // namespace

std::unique_ptr<GlContext> make_osmesa_context(int width, int height) {
    if (width < 1 || width > 16384)
        throw InputError("/width", "must be in [1, 16384], got " + std::to_string(width));
    if (height < 1 || height > 16384)
        throw InputError("/height", "must be in [1, 16384], got " + std::to_string(height));
    return std::make_unique<OsMesaContext>(width, height);
}

} // namespace polycut::render
