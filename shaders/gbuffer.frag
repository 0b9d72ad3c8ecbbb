// gbuffer.frag - the G-buffer pass's fragment shader (GLSL twin of sl_gbuffer_frag in
// src/raster/gbuffer_shader.c): writes what the lighting pass reads and nothing else.
// Targets: 0 world position (w = 1 marks a covered pixel), 1 unit world normal, 2 Kd, 3 Ks + alpha
// (1.w and 2.w the facet normal, facet_code);
// 4 occlusion + emission, "none" here, bound only for a scene with a material that writes them (the
// C twin leaves that plane alone: src/raster/gbuffer.h resolves it by depth).
// Depth is the fixed-function window depth (gl_FragCoord.z) in a DEPTH_COMPONENT32F target.
// An interpolated normal of zero length (opposite vertex normals) would make normalize() NaN;
// +Z is written instead, as the C twin does.
#version 330 core

in vec3 vWorldPos;
in vec3 vNormal;

uniform vec3 uKd;
uniform vec3 uKs;
uniform float uAlpha;

layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oKd;
layout(location = 3) out vec4 oKsAlpha;
layout(location = 4) out vec4 oExtra; // attached only when the scene has extra channels: "none"

// The facet normal (the triangle's plane: dFdx and dFdy of the position lie in it, and their cross
// product faces the viewer), octahedral-encoded into the normal's and Kd's spare .w channels:
// (2, 2) where the derivatives span no plane (the C side: sl_gbuffer.facet, src/raster/setup.c).
vec2 facet_code(vec3 dx, vec3 dy)
{
    vec3 f = cross(dx, dy);
    float l1 = abs(f.x) + abs(f.y) + abs(f.z);
    if (!(l1 > 0.0))
        return vec2(2.0);
    vec2 p = f.xy / l1;
    if (f.z < 0.0)
        p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
    return p;
}

void main()
{
    vec2 facet = facet_code(dFdx(vWorldPos), dFdy(vWorldPos));
    oPosition = vec4(vWorldPos, 1.0);
    oNormal = vec4(dot(vNormal, vNormal) > 1e-30 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0), facet.x);
    oKd = vec4(uKd, facet.y);
    oKsAlpha = vec4(uKs, uAlpha);
    oExtra = vec4(1.0, 0.0, 0.0, 0.0);
}
