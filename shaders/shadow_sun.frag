#version 330 core
// shadow_sun.frag - the env lights' orthographic maps' depth-only pass (GLSL twin of sun_frag and
// sun_masked_frag in src/shadow/shadow.c and the depth it keeps): each texel holds the depth along
// the map's axis, z0 + window depth * sz (the orthographic projection maps that depth linearly
// onto the window depth, sl_shadow_sun_view_proj); the depth test against the window depth keeps
// the nearest surface's. Drawn with shadow_depth.vert.

uniform float uDepthOrigin; // z0: the map's box's lowest depth along the axis
uniform float uDepthExtent; // sz: the box's extent along the axis

// A masked caster (uMasked != 0) is cut away where its coverage, mask_map's r or kd_map's a
// (uCoverageChannel 0 or 3) at the map's coordinate, read at level 0, is below the cutoff
// (src/raster/coverage.h; the same test in shadow_depth.frag and shadow_sun.frag).
uniform int uMasked;
uniform sampler2D uCoverageMap;
uniform vec4 uCoverageST;
uniform int uCoverageChannel;
uniform float uAlphaCutoff;

in vec2 vTexCoord;

bool masked_away()
{
    vec4 t = textureLod(uCoverageMap, vTexCoord * uCoverageST.xy + uCoverageST.zw, 0.0);
    return uMasked != 0 && (uCoverageChannel == 0 ? t.r : t.a) < uAlphaCutoff;
}

layout(location = 0) out float oDepth;

void main()
{
    if (masked_away())
        discard;
    oDepth = uDepthOrigin + gl_FragCoord.z * uDepthExtent;
}
