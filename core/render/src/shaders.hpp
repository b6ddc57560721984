// Private: GLSL 4.50 sources of the renderer's programs. Lit surfaces come in two variants:
// per-vertex (Gouraud) lighting, the default, and per-pixel (Phong). llvmpipe runs the fragment
// shader once per sample under MSAA, so the cheap fragment shader of the Gouraud variant saves
// about a quarter of a 4x MSAA frame; on surfaces this fine the two look alike.
#pragma once

namespace polycut::render::shaders {

/// Lit surfaces: per-vertex normal and colour, transformed to camera space.
inline constexpr const char* kLitVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_colour;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_position;
out vec3 v_normal;
out vec4 v_colour;
void main() {
    vec4 p = u_view * vec4(a_position, 1.0);
    v_position = p.xyz;
    v_normal = mat3(u_view) * a_normal;  // the view transform is rigid
    v_colour = a_colour;
    gl_Position = u_projection * p;
}
)";

/// Blinn-Phong with a key light (near the headlight) and a weaker fill light, both in camera
/// space, plus ambient; two-sided so that cut faces of either orientation are lit.
inline constexpr const char* kLitFragment = R"(#version 450 core
in vec3 v_position;
in vec3 v_normal;
in vec4 v_colour;
uniform vec3 u_key_direction;
uniform vec3 u_fill_direction;
uniform float u_ambient;
uniform float u_key;
uniform float u_fill;
uniform float u_specular;
uniform float u_shininess;
layout(location = 0) out vec4 o_colour;
void main() {
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing) n = -n;
    vec3 to_eye = normalize(-v_position);
    float key = max(dot(n, u_key_direction), 0.0);
    float fill = max(dot(n, u_fill_direction), 0.0);
    vec3 h = normalize(u_key_direction + to_eye);
    float highlight = key > 0.0 ? pow(max(dot(n, h), 0.0), u_shininess) : 0.0;
    vec3 c = v_colour.rgb * (u_ambient + u_key * key + u_fill * fill)
        + vec3(u_specular * u_key * highlight);
    o_colour = vec4(clamp(c, 0.0, 1.0), 1.0);
}
)";

/// Gouraud variant: the same lighting evaluated per vertex for both faces of the surface; the
/// fragment shader picks the side facing the camera.
inline constexpr const char* kGouraudVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_colour;
uniform mat4 u_view;
uniform mat4 u_projection;
uniform vec3 u_key_direction;
uniform vec3 u_fill_direction;
uniform float u_ambient;
uniform float u_key;
uniform float u_fill;
uniform float u_specular;
uniform float u_shininess;
out vec4 v_front;
out vec4 v_back;
vec4 shade(vec3 n, vec3 to_eye) {
    float key = max(dot(n, u_key_direction), 0.0);
    float fill = max(dot(n, u_fill_direction), 0.0);
    vec3 h = normalize(u_key_direction + to_eye);
    float highlight = key > 0.0 ? pow(max(dot(n, h), 0.0), u_shininess) : 0.0;
    vec3 c = a_colour.rgb * (u_ambient + u_key * key + u_fill * fill)
        + vec3(u_specular * u_key * highlight);
    return vec4(clamp(c, 0.0, 1.0), 1.0);
}
void main() {
    vec4 p = u_view * vec4(a_position, 1.0);
    vec3 n = normalize(mat3(u_view) * a_normal);
    vec3 to_eye = normalize(-p.xyz);
    v_front = shade(n, to_eye);
    v_back = shade(-n, to_eye);
    gl_Position = u_projection * p;
}
)";

inline constexpr const char* kGouraudFragment = R"(#version 450 core
in vec4 v_front;
in vec4 v_back;
layout(location = 0) out vec4 o_colour;
void main() { o_colour = gl_FrontFacing ? v_front : v_back; }
)";

/// Unlit lines (wireframe).
inline constexpr const char* kLineVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_colour;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec4 v_colour;
void main() {
    v_colour = a_colour;
    gl_Position = u_projection * u_view * vec4(a_position, 1.0);
}
)";

inline constexpr const char* kLineFragment = R"(#version 450 core
in vec4 v_colour;
layout(location = 0) out vec4 o_colour;
void main() { o_colour = v_colour; }
)";

} // namespace polycut::render::shaders
