#version 330 core
// shadow_depth.frag - the shadow maps' depth-only pass (GLSL twin of shadow_frag and
// shadow_masked_frag in src/shadow/shadow.c): each texel keeps the view depth along the map's
// axis, w of the clip position, which is 1 / gl_FragCoord.w; the depth test against the window
// depth keeps the nearest surface's.

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

layout(location = 0) out float oView;

void main()
{
    if (masked_away())
        discard;
    oView = 1.0 / gl_FragCoord.w;
}
