// Private: the one place that includes the GL headers. libOSMesa exports the GL entry points up
// to about 4.1 (not 4.5 direct state access), so GL_GLEXT_PROTOTYPES gives direct calls without
// a loader as long as the renderer keeps to bind-to-edit calls. An EGL backend would
// link libOpenGL instead and could keep these same calls.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
// osmesa.h includes GL/gl.h (compatibility declarations); glcorearb.h adds the core 4.5 API.
#include <GL/glcorearb.h>

namespace polycut::render::gl {

/// Throws polycut::Error naming `what` if glGetError() reports an error.
void check(const char* what);

/// Compiles and links a program from GLSL sources; throws polycut::Error with the info log.
GLuint link_program(const char* vertex_source, const char* fragment_source);

} // namespace polycut::render::gl
