#version 330 core
// shadow_depth.frag - the shadow maps' depth-only pass (GLSL twin of shadow_frag in
// src/shadow/shadow.c): each texel keeps the view depth along the map's axis, w of the clip
// position, which is 1 / gl_FragCoord.w; the depth test against the window depth keeps the
// nearest surface's.

layout(location = 0) out float oView;

void main()
{
    oView = 1.0 / gl_FragCoord.w;
}
