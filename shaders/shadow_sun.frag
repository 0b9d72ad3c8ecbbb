#version 330 core
// shadow_sun.frag - the env lights' orthographic maps' depth-only pass (GLSL twin of sun_frag in
// src/shadow/shadow.c and the depth it keeps): each texel holds the depth along the map's axis,
// z0 + window depth * sz (the orthographic projection maps that depth linearly onto the window
// depth, sl_shadow_sun_view_proj); the depth test against the window depth keeps the nearest
// surface's. Drawn with shadow_depth.vert.

uniform float uDepthOrigin; // z0: the map's box's lowest depth along the axis
uniform float uDepthExtent; // sz: the box's extent along the axis

layout(location = 0) out float oDepth;

void main()
{
    oDepth = uDepthOrigin + gl_FragCoord.z * uDepthExtent;
}
